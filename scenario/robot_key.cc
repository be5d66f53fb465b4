// The archives' walk of the `robot` key (robot_key.h): a name, or a design read over its
// preset.
#include "scenario/robot_key.h"

#include <stdexcept>

#include "scenario/archive.h"

namespace climbsim::sim {

bool IsRobotPath(const std::string& name) {
  return name.find('/') != std::string::npos || name.ends_with(".xml");
}

void YamlReadArchive::Visit(const Field& f, RobotKey* robot) {
  Place(f);
  if (f.required && !map_.Has(f.key)) throw map_.Error(f.key, "is required");
  if (!map_.Raw(f.key).IsMap()) {
    *robot->name = map_.RequiredString(f.key);
    robot->design->reset();
    return;
  }
  // The preset first: the design starts as it, and the other keys change it (a key the map
  // does not give keeps the preset's value).
  YamlMap given = map_.Map(f.key);
  const std::string preset = given.String("preset", kDocumentedPreset);
  try {
    robot->design->emplace(PresetDesign(preset));
  } catch (const std::invalid_argument& e) {
    throw given.Error("preset", e.what());
  }
  YamlReadArchive sub(map_.Map(f.key), places_);
  sub.Read(&**robot->design);
  *robot->name = (*robot->design)->preset;
}

void YamlWriteArchive::Visit(const Field& f, RobotKey* robot) {
  // A design is written whole (every key, its preset's values included): the resolved file
  // reruns the same body even if a preset changes later.
  if (robot->design->has_value()) {
    node_[std::string(f.key)] = Write(**robot->design);
  } else {
    node_[std::string(f.key)] = *robot->name;
  }
}

void DocArchive::Visit(const Field& f, RobotKey*) {
  Add(f, "(none)");
  DocArchive sub;
  sub.prefix = prefix + std::string(f.key) + ".";
  RobotDesign design = PresetDesign(kDocumentedPreset);
  design.Serialize(&sub);
  rows.insert(rows.end(), sub.rows.begin(), sub.rows.end());
}

}  // namespace climbsim::sim
