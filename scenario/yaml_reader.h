// Reading YAML with the place of every value: each getter validates type and range and, on
// failure, throws climbsim::InputError naming file:line:col and the dotted key. A map
// remembers which keys were read so that CheckNoUnknownKeys() can reject the rest (a typo
// must not silently fall back to a default). Internal to scenario/.
#ifndef CLIMBSIM_SCENARIO_YAML_READER_H_
#define CLIMBSIM_SCENARIO_YAML_READER_H_

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "common/common.h"
#include "keys/keys.h"

namespace climbsim::sim {

// Bounds on what a YAML file may hold: a scenario file is a few kB; without bounds /dev/zero
// or a 58 MB file would take gigabytes of memory before any check.
inline constexpr size_t kMaxYamlFileBytes = 4u << 20;  // 4 MiB
inline constexpr size_t kMaxYamlListLength = 10000;    // items of a list, keys of a map
// Nodes of the tree with every alias expanded: yaml-cpp shares an anchor's node between its
// aliases, and each walk of the tree (the readers, YAML::Clone's users) visits it again.
inline constexpr size_t kMaxYamlNodes = 100000;

// Reads a whole file: a regular file (or a pipe) of at most kMaxYamlFileBytes holding one YAML
// document within the bounds of CheckYamlShape. A YAML syntax error, a folder, a device, a
// second document ('---') or a bound exceeded is an InputError at its place.
YAML::Node LoadYamlFile(const std::string& path);
// The same checks for YAML text already read (the Python binding's scenario_from_yaml);
// `path` names it in messages.
YAML::Node LoadYamlText(const std::string& text, const std::string& path);

// The bounds above on a tree read by other means (YAML::Load of a text): lists and maps at
// most kMaxYamlListLength long, 64 deep, kMaxYamlNodes nodes with aliases expanded. Stops at
// the first excess, so it costs at most kMaxYamlNodes steps; throws InputError at its place
// (file:line:col of the node, the dotted key with [i] for list items). ParseScenario calls it
// first, whatever read the tree.
void CheckYamlShape(const YAML::Node& root, const std::string& file);

// "" when `text` holds no control character (bytes below 0x20, and 0x7f), else what is
// wrong ("must not contain control characters (0x0d at 15)"). Names and paths never hold
// one, and the resolved scenario could not write it back (yaml-cpp emits a carriage return
// unquoted, which then reads as a line break).
std::string ControlCharacterProblem(std::string_view text);

class YamlMap {
 public:
  // `node` must be a map or null (null reads as an empty map); `path` is the dotted prefix of
  // its keys in messages ("cpg"), empty at the top level.
  YamlMap(const YAML::Node& node, std::string file, std::string path);

  bool Has(std::string_view key) const;

  // Optional values with defaults. Absent keys take the default; present ones are checked.
  double Double(std::string_view key, double default_value, Range range = Range::Any());
  int Int(std::string_view key, int default_value, int lo, int hi);
  bool Bool(std::string_view key, bool default_value);
  std::string String(std::string_view key, const std::string& default_value);
  std::string Choice(std::string_view key, const std::string& default_value,
                     const std::vector<std::string>& allowed);
  // A list of numbers; `size` 0 accepts any non-empty length.
  std::vector<double> Doubles(std::string_view key, const std::vector<double>& default_value,
                              size_t size, Range range = Range::Any());
  // A list of lists with `rows` x `cols` numbers.
  std::vector<std::vector<double>> Matrix(std::string_view key, size_t rows, size_t cols,
                                          Range range = Range::Any());

  double RequiredDouble(std::string_view key, Range range = Range::Any());
  std::string RequiredString(std::string_view key);

  // A nested map (an empty one when the key is absent or null).
  YamlMap Map(std::string_view key);
  // The raw node of a key, marked as read (for values with several accepted shapes).
  YAML::Node Raw(std::string_view key);

  // Throws for the first key that no getter asked for.
  void CheckNoUnknownKeys() const;

  // An error at the key's value (or at this map when the key is absent).
  InputError Error(std::string_view key, const std::string& message) const;
  InputError ErrorAt(const YAML::Node& node, std::string_view key,
                     const std::string& message) const;
  std::string KeyPath(std::string_view key) const;
  const std::string& file() const { return file_; }
  const YAML::Node& node() const { return node_; }

 private:
  YAML::Node Get(std::string_view key);  // marks the key used; undefined node when absent
  double ToDouble(const YAML::Node& value, std::string_view key) const;

  YAML::Node node_;
  std::string file_;
  std::string path_;
  YAML::Mark mark_;
  std::set<std::string, std::less<>> used_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_YAML_READER_H_
