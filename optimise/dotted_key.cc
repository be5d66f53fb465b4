// The dotted keys live beside the scenario (scenario/dotted_key.h), where --set and the
// Python Scenario use them too; optimise keeps its names for them.
#include "optimise/optimise.h"
#include "scenario/dotted_key.h"

namespace climbsim::optimise {

void SetDottedKey(YAML::Node root, std::string_view key, double value) {
  sim::SetDottedKey(root, key, value);
}

void SetDottedKeyText(YAML::Node root, std::string_view key, const std::string& text) {
  sim::SetDottedKeyText(root, key, text);
}

double GetDottedKey(const YAML::Node& root, std::string_view key) {
  return sim::GetDottedKey(root, key);
}

}  // namespace climbsim::optimise
