// Dotted keys of a scenario tree ("cpg.frequency_hz", "cpg.stride_rad[0]",
// "cpg.phase_bias_rad[0][1]", "reflex.preload.gain"): what `optimise` tunes, what `sweep`
// sweeps, what `--set KEY=VALUE` replaces on every verb that reads a scenario file, and what
// a Python Scenario's s["key"] reads and writes. One walk serves them all.
#ifndef CLIMBSIM_SCENARIO_DOTTED_KEY_H_
#define CLIMBSIM_SCENARIO_DOTTED_KEY_H_

#include <yaml-cpp/yaml.h>

#include <string>
#include <string_view>
#include <vector>

namespace climbsim::sim {

// Set creates a missing map key (maps on the way; "scene: wall" and "robot: gecko" become
// their maps); a list element must exist. All throw std::invalid_argument with a message
// naming the part of the key that does not fit.
void SetDottedKey(YAML::Node root, std::string_view key, double value);
// Any scalar given as its YAML text ("physics.integrator" = "euler").
void SetDottedKeyText(YAML::Node root, std::string_view key, const std::string& text);
// Any node: a scalar, a list or a map replaces what the key held.
void SetDottedKeyNode(YAML::Node root, std::string_view key, const YAML::Node& value);
double GetDottedKey(const YAML::Node& root, std::string_view key);
// The node the key names (a copy), or an invalid_argument when the tree lacks it.
YAML::Node GetDottedKeyNode(const YAML::Node& root, std::string_view key);
// Removes a map key (a list item cannot be removed); invalid_argument when the tree lacks it.
void RemoveDottedKey(YAML::Node root, std::string_view key);
// Every key of the tree that holds a scalar, dotted, list items as [i], in the tree's order.
std::vector<std::string> DottedKeys(const YAML::Node& root);

// A key replaced from outside the file: `--set KEY=VALUE` on the command line.
struct KeyOverride {
  std::string key;
  std::string value;  // YAML text: a scalar, or a flow list or map ("[0.3, 0.3]")
  std::string Flag() const { return "--set " + key + "=" + value; }
};

// "KEY=VALUE" → its override; an InputError naming the flag when there is no '=' or the key
// is not a dotted key.
KeyOverride ParseKeyOverride(const std::string& text);

// Writes the overrides into a scenario tree read from `file`, then checks the result as the
// scenario loader does: a value refused at an overridden key (or under it) is an InputError
// naming the flag ("--set cpg.frequency_hz=abc: cpg.frequency_hz: ..."); another one is the
// file's own error.
void ApplyKeyOverrides(YAML::Node root, const std::vector<KeyOverride>& overrides,
                       const std::string& file);

// The command line's overrides: a verb sets them once, before it reads any scenario file;
// LoadYamlFile (every scenario file a verb reads: simulate's, each of sweep's, optimise's
// and its workers', bench's) applies them, and the resolved scenario.yaml names them.
// Empty unless a command line gave --set; the library's other users never see any.
void SetCommandLineKeys(std::vector<KeyOverride> overrides);
const std::vector<KeyOverride>& CommandLineKeys();

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_DOTTED_KEY_H_
