// The scenario's adhesion block: the keys of the pads' own structs (PadParams, AttachParams,
// FrictionalParams declare theirs beside their fields) and what only a scenario has (which
// pads, which surfaces, per-pad overrides, disturbances). sim/adhesion_effect.h builds the
// AdhesionSystem from it; adhesion/README.md has the model.
#ifndef CLIMBSIM_ADHESION_PARAMS_H_
#define CLIMBSIM_ADHESION_PARAMS_H_

#include <optional>
#include <string>
#include <vector>

#include "adhesion/adhesion_system.h"
#include "adhesion/bond_grid.h"
#include "adhesion/frictional_law.h"
#include "adhesion/sticky_pad.h"
#include "adhesion/tabulated_law.h"
#include "keys/keys.h"

namespace climbsim::adhesion {

// Dry adhesion (adhesion/README.md has the model; docs/design.md section 3). Material and attach
// keys apply to every pad; pad_overrides changes a few of them for one pad.
struct PadOverride {
  std::string pad;
  std::optional<double> sigma_t_pa;
  std::optional<double> mu;
  std::optional<double> gain_n;
  std::optional<double> grip_x;
  std::optional<double> grip_y;

  template <class A>
  void Serialize(A* a) {
    a->Visit({"pad", "", "the pad body this entry changes (one of adhesion.pads)", {}, true}, &pad);
    a->Visit({"sigma_t_pa", "Pa", "this pad's rupture threshold", Range::Positive()}, &sigma_t_pa);
    a->Visit({"mu", "", "this pad's compression gain", Range::NonNegative()}, &mu);
    a->Visit({"gain_n", "N", "this pad's adhesion-actuator gain (model mujoco)", Range::Positive()},
             &gain_n);
    a->Visit({"grip_x", "",
              "this pad's gripping direction, x component (law frictional; pad frame, as "
              "adhesion.frictional.grip_x): e.g. hind feet gripping up the wall, opposed to the "
              "front feet",
              Range::Any()},
             &grip_x);
    a->Visit(
        {"grip_y", "", "this pad's gripping direction, y component (law frictional)", Range::Any()},
        &grip_y);
  }
};

// The bond grid's keys (PadParams: one declaration and one default each; width_m
// and length_m are not keys, they come from each pad's box geom) and the attach conditions
// (AttachParams), plus what only the scenario has.
struct AdhesionKeys : PadParams, AttachParams, PartialContactParams {
  std::string model = "bonds";
  std::vector<std::string> pads;
  std::vector<std::string> surfaces;
  bool start_attached = AdhesionSystemParams{}.start_attached;
  double start_gap_m = AdhesionSystemParams{}.start_gap_m;
  std::vector<double> weld_solref =
      std::vector<double>(kDefaultWeldSolref.begin(), kDefaultWeldSolref.end());
  std::optional<double> gain_n;
  double ctrl = StickyPadParams{}.actuator_ctrl;
  double reach_m = AdhesionSystemParams{}.reach_m;
  std::vector<PadOverride> pad_overrides;
  double pad_failure_probability = 0.0;
  double pad_failure_window_s = 1.0;
  std::string law = "von_mises";
  FrictionalParams frictional;
  TabulatedParams tabulated;
  double release_contact_delay_s = StickyPadParams{}.release_contact_delay_s;

  template <class A>
  void Serialize(A* a) {
    a->Choice({"model", "",
               "bonds: this project's weld-and-bond-grid model; mujoco: MuJoCo's built-in adhesion "
               "actuator (the baseline)"},
              &model, {"bonds", "mujoco"});
    a->Visit({"pads", "",
              "sticky pad bodies (each holds one box geom); default: every leg's pad body (LF_pad, "
              "RF_pad, ...)"},
             &pads);
    a->Visit({"surfaces", "",
              "bodies or geoms the pads may stick to; default: any geom that is not a sticky pad"},
             &surfaces);
    a->Visit({"start_attached", "",
              "pads within start_gap_m of a surface at t = 0 attach fully, without the attach "
              "conditions (a robot that starts on a wall or a ceiling)"},
             &start_attached);
    a->Visit({"start_gap_m", "m",
              "how far a pad face may be from a surface at t = 0 and still start attached (the "
              "robots start 0.5 mm above it)",
              Range::OpenClosed(0, 0.1)},
             &start_gap_m);
    PadParams::Serialize(a);     // sigma_t_pa, mu, grid_x, grid_y, min_bonds
    AttachParams::Serialize(a);  // min_contacts .. attach_window_s
    PartialContactParams::Serialize(a);  // partial_contact, contact_gap_m
    a->Visit({"weld_solref", "s, -",
              "solref (time constant, damping ratio) of the welds that hold attached pads; MuJoCo "
              "raises the time constant to 2 time steps",
              Range::Positive()},
             &weld_solref, 2);
    a->Visit({"gain_n", "N",
              "model mujoco: adhesion-actuator force at ctrl 1; default sigma_T times the pad area",
              Range::Positive()},
             &gain_n);
    a->Visit({"ctrl", "", "model mujoco: actuator ctrl while attached", Range::Closed(0, 1)},
             &ctrl);
    a->Visit(
        {"reach_m", "m",
         "model mujoco: pad geom margin = gap, so the actuator pulls a pad this close to a surface",
         Range::Closed(0, 0.1)},
        &reach_m);
    a->Visit({"pad_overrides", "",
              "per-pad changes: a list of maps with pad and any of sigma_t_pa, mu, gain_n, grip_x, "
              "grip_y"},
             &pad_overrides);
    a->Visit({"pad_failure_probability", "",
              "each attachment fails with this probability (drawn from seed): all its bonds break "
              "at once (detach cause failure) at a time uniform in [0, pad_failure_window_s) after "
              "the attach, if the pad still holds then",
              Range::Closed(0, 1)},
             &pad_failure_probability);
    a->Visit({"pad_failure_window_s", "s",
              "pad failures: the window after an attach in which a failing pad fails (about one "
              "stance of the example gaits: 1.25 s gecko, 0.95 s spider)",
              Range::Positive()},
             &pad_failure_window_s);
    a->Choice({"law", "",
               "model bonds: when bonds break. von_mises: the seed's isotropic law (sigma_T, mu); "
               "frictional: directional dry adhesion, adhesion only under shear along the gripping "
               "direction (adhesion.frictional); tabulated: a lab's measured pull-off against angle "
               "(adhesion.tabulated, written by climbsim fit-adhesion)"},
              &law, {"von_mises", "frictional", "tabulated"});
    a->Visit({"frictional", "", "the frictional law's parameters (law: frictional)"}, &frictional);
    a->Visit({"tabulated", "",
              "the tabulated law's table (law: tabulated): measured pull-off against the angle "
              "from the pad normal"},
             &tabulated);
    a->Visit({"release_contact_delay_s", "s",
              "model bonds: a pad let go by its release (detach cause released) collides again "
              "only this much later, so that it is not pushed out of the depth its landing pressed "
              "it to (a kick the other pads feel); 0 = at once",
              Range::NonNegative()},
             &release_contact_delay_s);
  }

  void Validate(const Checker& c) const {
    PadParams::Validate(c);
    if (law == "tabulated" && tabulated.angle_from_normal_deg.empty()) {
      c.Fail("tabulated", "law tabulated needs a table: adhesion.tabulated.angle_from_normal_deg "
                          "and pulloff_n (climbsim fit-adhesion writes one)");
    }
  }
};

}  // namespace climbsim::adhesion

#endif  // CLIMBSIM_ADHESION_PARAMS_H_
