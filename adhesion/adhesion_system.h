// Every sticky pad of a model, and what they need from the MJCF: the MuJoCo side of the
// adhesion model, independent of climbsim's scenario files (sim/adhesion_effect.h adapts it
// to them; the pull-off rig and the tests drive it directly).
//
//   1. Before compiling: AdhesionMjcf(pads, ...) gives the <equality> lines (kBonds: one
//      inactive weld per pad, body1 = pad, body2 = world for now, solref weld_solref) or the
//      <actuator> lines (kMujoco: one <adhesion> actuator per pad, ctrlrange 0 1).
//   2. AdhesionSystem(model, params): resolves every name once (pad bodies, their box geoms,
//      welds, actuators, surfaces) and sizes every buffer.
//   3. Per run: Reset after mj_resetData; then BeforeStep, mj_step, AfterStep each step.
//
// SURFACES. The geoms a pad may stick to: the geoms of the named bodies plus the named geoms;
// by default every geom that is not a sticky pad's. Contacts with other geoms are ordinary.
//
// START ATTACHED. With start_attached, Reset attaches (fully, without the conditions, event
// cause "start_attached") every pad whose face is within start_gap_m of a surface: the robots
// of mjcf/ start with their pads 0.5 mm above the surface, and on a wall or a ceiling gravity
// never brings them down. The distance test runs MuJoCo's collision with the pad geoms' margin
// set to start_gap_m for that one call; the welds hold the pads where they are.
//
// kMujoco REACH. MuJoCo's adhesion actuator acts only through contacts, and contacts in a
// geom's gap (margin − gap < dist < margin) carry no contact force but do carry the
// actuator's: each pad geom gets margin = gap = reach_m, so that the actuator pulls a pad that
// is up to reach_m from the surface (measured on 2.2.2).
//
// Nothing allocates after construction.
#ifndef CLIMBSIM_ADHESION_ADHESION_SYSTEM_H_
#define CLIMBSIM_ADHESION_ADHESION_SYSTEM_H_

#include <mujoco/mujoco.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "adhesion/sticky_pad.h"

namespace climbsim::adhesion {

struct PadSpec {
  std::string body;        // the pad body (holds exactly one box geom)
  StickyPadParams params;  // width and length come from the box
};

struct AdhesionSystemParams {
  std::vector<PadSpec> pads;
  std::vector<std::string> surfaces;  // body or geom names; empty: any non-sticky geom
  bool start_attached = false;
  double start_gap_m = 0.001;  // > 0
  double reach_m = 0.001;      // kMujoco: pad geom margin = gap, ≥ 0
};

// The MJCF lines the pads need (without the enclosing <equality>/<actuator> tags). Welds are
// named WeldName(body), actuators AdhesionActuatorName(body) (weld.h).
// (time constant s, damping ratio) of the welds that hold attached pads, unless given.
inline constexpr std::array<double, 2> kDefaultWeldSolref{0.002, 1.0};

struct AdhesionMjcfText {
  std::string equality;
  std::string actuator;
};
AdhesionMjcfText AdhesionMjcf(const std::vector<PadSpec>& pads,
                              const std::array<double, 2>& weld_solref);

// A name that does not resolve. key() says which list it came from: "pads" or "surfaces".
class AdhesionSetupError : public std::invalid_argument {
 public:
  AdhesionSetupError(std::string key, const std::string& message)
      : std::invalid_argument(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

class AdhesionSystem {
 public:
  // Throws AdhesionSetupError for a pad body or surface that does not exist or a pad without
  // exactly one box geom, std::invalid_argument for bad parameters.
  AdhesionSystem(const mjModel* m, const AdhesionSystemParams& params);

  // After mj_resetData: every pad detached and every model-level switch restored; then the
  // start attachment (may call mj_fwdPosition and mj_forward). Events go to `sink` (may be
  // null).
  void Reset(mjModel* m, mjData* d, PadEventSink* sink);
  // Sense every pad, then decide for every pad (events stamped d->time).
  void BeforeStep(mjModel* m, mjData* d, PadEventSink* sink);
  // Loads, bonds and detachments of this step (events stamped d->time, the step's end).
  void AfterStep(mjModel* m, mjData* d, PadEventSink* sink);
  // Detaches pad `pad` now with cause "released"; false when it was not attached.
  bool Release(int pad, mjModel* m, mjData* d, PadEventSink* sink);

  int size() const { return static_cast<int>(pads_.size()); }
  StickyPad& pad(int i) { return pads_[i]; }
  const StickyPad& pad(int i) const { return pads_[i]; }
  const std::string& pad_name(int i) const { return names_[i]; }
  // The pad whose body is `body`, or −1.
  int FindPad(int body) const;
  const std::vector<uint8_t>& sticks_to() const { return sticks_to_; }
  const AdhesionSystemParams& params() const { return params_; }

 private:
  void StartAttached(mjModel* m, mjData* d, PadEventSink* sink);
  int AddPad(const mjModel* m, const PadSpec& spec);
  void ResolveSurfaces(const mjModel* m, const std::vector<uint8_t>& sticky);

  AdhesionSystemParams params_;
  std::vector<StickyPad> pads_;
  std::vector<std::string> names_;
  std::vector<uint8_t> sticks_to_;  // per geom
};

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_ADHESION_SYSTEM_H_
