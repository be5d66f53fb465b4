// The MuJoCo side of a run. CompiledModel composes a robot file, a scene file and what the
// effects add (welds, sensors, actuators) into one model and reads the robot contract of
// mjcf/README.md (legs, joints, pads). It depends only on the scenario's structure (robot,
// scene, which effects), is compiled once and never changes. Each run owns a World: its own
// mj_copyModel, on which the scenario's values (physics options, incline gravity, initial
// pose, payload) are set, and its mjData. Runs never share a model: MuJoCo 2.2.2 keeps run-time
// switches such as eq_active in mjModel.
#ifndef CLIMBSIM_SIM_WORLD_H_
#define CLIMBSIM_SIM_WORLD_H_

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "robot/robot.h"
#include "scenario/scenario.h"

namespace climbsim::sim {

// MJCF sections added to the composed model, as XML text.
struct MjcfAdditions {
  std::string top;  // whole top-level elements (scene.terrain's <size> and <asset>)
  std::string equality;
  std::string sensor;
  std::string actuator;
  std::string contact;
  std::string worldbody;  // geoms of the world body (scene.roughness's bumps, scene.terrain)
};

struct SceneInfo {
  Eigen::Vector3d travel{1, 0, 0};     // progress = travel · displacement of the base
  Eigen::Vector3d gravity{0, 0, -9.81};  // the scene file's (an incline rotates it per World)
};

class CompiledModel {
 public:
  // Composes and compiles robot, scene and additions (the scenario's values are applied per
  // World); throws InputError (at the scenario's robot key) when MuJoCo rejects the model
  // or the robot lacks a contract item.
  static std::unique_ptr<CompiledModel> Build(const Scenario& scenario,
                                              const MjcfAdditions& additions);
  ~CompiledModel();
  CompiledModel(const CompiledModel&) = delete;
  CompiledModel& operator=(const CompiledModel&) = delete;

  const mjModel* model() const { return model_; }
  // The composed model, self-contained (includes expanded): the text MuJoCo compiled.
  const std::string& xml() const { return xml_; }
  const RobotInfo& robot() const { return robot_; }
  const SceneInfo& scene() const { return scene_; }

 private:
  CompiledModel() = default;
  mjModel* model_ = nullptr;
  std::string xml_;
  RobotInfo robot_;
  SceneInfo scene_;
  double spawn_offset_[3] = {0, 0, 0};
};

// The options a model steps with, as scenario keys, every one set: what a run records in
// its resolved scenario.yaml.
PhysicsParams PhysicsOf(const mjModel* model);

// One run's model copy and data.
class World {
 public:
  // Copies the model and sets the scenario's physics options (those it gives; the others stay
  // as the scene file has them), gravity and initial pose. A payload (payload_kg) scales the
  // base body's mass and inertia by (m_base + payload)/m_base (the payload spread like the
  // base's own mass: same centre of mass, same radii of gyration), then mj_setConst
  // recomputes what depends on masses (subtree masses, the constraint solver's inverse
  // weights).
  World(const CompiledModel& compiled, const Scenario& scenario);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  mjModel* model() { return model_; }
  const mjModel* model() const { return model_; }
  mjData* data() { return data_; }
  const mjData* data() const { return data_; }
  const RobotInfo& robot() const { return compiled_.robot(); }
  const SceneInfo& scene() const { return compiled_.scene(); }
  // Gravity of this run (the scene's, rotated for an incline).
  const Eigen::Vector3d& gravity() const { return gravity_; }
  const CompiledModel& compiled() const { return compiled_; }
  // Records the state the run starts from (Simulation::Reset calls it after the initial pose).
  void MarkStart();
  // This run's model as one self-contained MJCF file (the run folder's model.xml): the
  // compiled text (every include expanded, climbsim's welds, sensors and actuators) plus an
  // <option> with this run's physics values (timestep, gravity after an incline's rotation,
  // solver) and a keyframe "climbsim_start" with the starting qpos (spawn and initial pose).
  // `mujoco-compile model.xml` compiles it from any folder; no file outside it is read.
  std::string Xml() const;

 private:
  const CompiledModel& compiled_;
  mjModel* model_;
  mjData* data_ = nullptr;
  Eigen::Vector3d gravity_;
  std::vector<double> start_qpos_;
};

// A model's custom numeric `name` with at least `size` numbers into out; false when absent.
bool CustomNumeric(const mjModel* model, const char* name, int size, double* out);

// The composed top-level MJCF for a robot and a scene file (absolute paths).
std::string ComposeMjcf(const std::string& robot_file, const std::string& scene_file,
                        const MjcfAdditions& additions);
// The scenario's robot file text: generated (robot/design.h) for a preset or a design, read
// for a path. A design the generator refuses is an InputError at the robot key.
std::string RobotMjcf(const Scenario& scenario);
// The scenario's composed top-level MJCF, before ExpandIncludes: ComposeMjcf for a robot
// file; for a preset or a design, its generated root children spliced in where the include
// would be expanded (between the same "climbsim: begin of" and "end of" comments). Equal
// texts compile to equal models: the key of a cache of compiled models.
std::string ComposeScenarioMjcf(const Scenario& scenario, const MjcfAdditions& additions);

// `xml` with every <include file="..."/> replaced by the included file's root children (its
// own includes expanded in turn; relative names resolve against base_dir, or against the
// including file's folder inside an included file), each between "climbsim: begin of NAME"
// and "end of NAME" comments (the file name only). Throws std::runtime_error when a file cannot be
// read. Asset files are not copied here (CarryMeshes makes a run folder carry its meshes).
std::string ExpandIncludes(const std::string& xml, const std::string& base_dir, int depth = 0);

// A run folder carries the mesh files its model reads, in this subfolder beside model.xml.
inline constexpr const char* kRunMeshDir = "meshes/";

// A model text made to travel: every <mesh file="..."> names a copy in meshes/ beside the
// model (the file's own name; stem_2.ext and so on when two files share one), and every
// meshdir is "meshes/" (one is added when none was given). `meshes` lists each file read (an
// absolute path, resolved as MuJoCo 2.2.2 resolves it for the composed model) and its name
// there. A model that reads no mesh file comes back unchanged, byte for byte.
struct CarriedModel {
  struct Mesh {
    std::string source;  // the file the model read
    std::string name;    // its name in meshes/
  };
  std::string xml;
  std::vector<Mesh> meshes;
};
CarriedModel CarryMeshes(const std::string& xml);

// A run folder's model.xml made compilable from its text (common::CompileMjcfString, whose
// relative paths resolve against the working folder): meshdir set to run_dir's meshes/ as an
// absolute path. Unchanged when run_dir has no meshes/.
std::string WithRunMeshes(const std::string& xml, const std::string& run_dir);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_WORLD_H_
