// ChangedKeys: a design's keys flattened in declaration order (Serialize) and compared with its
// preset's, for the generated file's header and for messages.
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "robot/design.h"
#include "robot/mjcf_dom.h"

namespace climbsim::sim {

namespace {

template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};
template <class T>
struct IsVector : std::false_type {};
template <class T>
struct IsVector<std::vector<T>> : std::true_type {};

// Walks a Serialize declaration and writes each leaf key as ("legs.femur_m", "0.06").
class KeyLister {
 public:
  explicit KeyLister(std::string prefix = "") : prefix_(std::move(prefix)) {}

  template <class T>
  void Visit(const Field& f, T* v) {
    Add(prefix_ + std::string(f.key), *v);
  }
  template <class T>
  void Visit(const Field& f, T* v, size_t) {
    Add(prefix_ + std::string(f.key), *v);
  }
  template <class T>
  void Choice(const Field& f, T* v, const std::vector<std::string>&) {
    Add(prefix_ + std::string(f.key), *v);
  }
  std::vector<std::pair<std::string, std::string>> keys;

 private:
  template <class T>
  void Add(const std::string& name, T& v) {
    if constexpr (std::is_same_v<T, std::string>) {
      keys.emplace_back(name, v);
    } else if constexpr (std::is_same_v<T, bool>) {
      keys.emplace_back(name, v ? "true" : "false");
    } else if constexpr (std::is_arithmetic_v<T>) {
      keys.emplace_back(name, MjcfNumber(static_cast<double>(v)));
    } else if constexpr (IsOptional<T>::value) {
      if (v)
        Add(name, *v);
      else
        keys.emplace_back(name, "none");
    } else if constexpr (IsVector<T>::value) {
      keys.emplace_back(name + ".size", std::to_string(v.size()));
      for (size_t i = 0; i < v.size(); ++i) Add(name + "[" + std::to_string(i) + "]", v[i]);
    } else {
      KeyLister inner(name + ".");
      v.Serialize(&inner);
      keys.insert(keys.end(), inner.keys.begin(), inner.keys.end());
    }
  }
  std::string prefix_;
};

std::vector<std::pair<std::string, std::string>> Keys(RobotDesign design) {
  KeyLister lister;
  design.Serialize(&lister);
  return lister.keys;
}

}  // namespace

std::vector<std::string> ChangedKeys(const RobotDesign& design) {
  const auto keys = Keys(design), preset = Keys(PresetDesign(design.preset));
  std::vector<std::string> changed;
  for (const auto& [key, value] : keys) {
    if (key == "preset" || key.ends_with(".size")) continue;
    bool same = false;
    for (const auto& [preset_key, preset_value] : preset)
      if (preset_key == key) same = preset_value == value;
    if (!same) changed.push_back(key + " " + value);
  }
  return changed;
}

}  // namespace climbsim::sim
