// The scenario's adhesion block (adhesion/README.md has the model).
#ifndef CLIMBSIM_SCENARIO_ADHESION_KEYS_H_
#define CLIMBSIM_SCENARIO_ADHESION_KEYS_H_

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"
#include "adhesion/frictional_law.h"
#include "keys/keys.h"

namespace climbsim::sim {

// Dry adhesion (adhesion/README.md has the model; docs/design.md section 3). Material and attach
// keys apply to every pad; pad_overrides changes a few of them for one pad.
struct AdhesionPadOverride {
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

// adhesion.frictional: the directional law's parameters (adhesion/frictional_law.h; used
// with adhesion.law: frictional).
struct FrictionalKeys : adhesion::FrictionalParams {
  template <class A>
  void Serialize(A* a) {
    a->Visit({"critical_angle_deg", "deg",
              "alpha*: a pulled pad holds while F_n <= F_t tan(alpha*) (Autumn et al. 2006: about "
              "25-30 deg for geckos)",
              Range{0.0, 90.0, true, true}},
             &critical_angle_deg);
    a->Visit({"shear_limit_pa", "Pa",
              "tau_max: the shear limit F_t,max = tau_max times the pad area (also per bond)",
              Range::Positive()},
             &shear_limit_pa);
    a->Visit({"friction_mu", "",
              "Coulomb friction of a pressed pad: reversed shear up to mu C, gripping shear up to "
              "F_t,max + mu C (C the compression)",
              Range::NonNegative()},
             &friction_mu);
    a->Visit({"grip_x", "",
              "gripping direction d in the pad frame, x component (x across the pad width, along "
              "the heading for the bundled robots); normalised; default -1: down the wall for a "
              "robot climbing +x",
              Range::Any()},
             &grip_x);
    a->Visit({"grip_y", "",
              "gripping direction d in the pad frame, y component (y along the pad length); a "
              "climber's d points down the wall",
              Range::Any()},
             &grip_y);
    a->Visit({"moment_share", "",
              "share of the pad's moments the bonds carry: 1 a rigid pad on a rigid ankle (moments "
              "peel it bond by bond); 0 a compliant toe or passive ankle (the pad-level law)",
              Range::Closed(0, 1)},
             &moment_share);
  }
  void Validate(const Checker& c) const {
    if (!(std::hypot(grip_x, grip_y) > 1e-9))
      c.Fail("grip_x", "the gripping direction (grip_x, grip_y) must not be zero");
  }
};

// The bond grid's keys (adhesion::PadParams: one declaration and one default each; width_m
// and length_m are not keys, they come from each pad's box geom) and the attach conditions
// (adhesion::AttachParams), plus what only the scenario has.
struct AdhesionParams : adhesion::PadParams, adhesion::AttachParams {
  std::string model = "bonds";
  std::vector<std::string> pads;
  std::vector<std::string> surfaces;
  bool start_attached = adhesion::AdhesionSystemParams{}.start_attached;
  double start_gap_m = adhesion::AdhesionSystemParams{}.start_gap_m;
  std::vector<double> weld_solref =
      std::vector<double>(adhesion::kDefaultWeldSolref.begin(), adhesion::kDefaultWeldSolref.end());
  std::optional<double> gain_n;
  double ctrl = adhesion::StickyPadParams{}.actuator_ctrl;
  double reach_m = adhesion::AdhesionSystemParams{}.reach_m;
  std::vector<AdhesionPadOverride> pad_overrides;
  double pad_failure_probability = 0.0;
  double pad_failure_window_s = 1.0;
  std::string law = "von_mises";
  FrictionalKeys frictional;
  double release_contact_delay_s = adhesion::StickyPadParams{}.release_contact_delay_s;

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
    a->Visit({"sigma_t_pa", "Pa",
              "sigma_T, bond rupture threshold (10 kPa: the seed authors' estimate for their dry "
              "adhesive)",
              Range::Positive()},
             &sigma_t_pa);
    a->Visit({"mu", "",
              "gain of compression on the shear threshold: a compressed bond breaks when sqrt(3) "
              "times its shear reaches sigma_T + mu times its compression",
              Range::NonNegative()},
             &mu);
    a->Visit({"grid_x", "", "bonds across the pad width (accuracy against time)",
              Range::Closed(1, 1024)},
             &grid_x);
    a->Visit({"grid_y", "", "bonds along the pad length", Range::Closed(1, 1024)}, &grid_y);
    a->Visit({"min_bonds", "", "the pad detaches when fewer bonds than this remain",
              Range::Closed(1, 1048576)},
             &min_bonds);
    a->Visit({"min_contacts", "",
              "attach condition: contact points with the surface (box on plane gives 4)",
              Range::Closed(1, 1000)},
             &min_contacts);
    a->Visit(
        {"max_approach_speed_mps", "m/s",
         "attach condition: normal speed towards the surface at touchdown", Range::NonNegative()},
        &max_approach_speed_mps);
    a->Visit({"max_approach_angle_deg", "deg",
              "attach condition: angle between pad normal and surface normal at touchdown",
              Range::Closed(0, 180)},
             &max_approach_angle_deg);
    a->Visit({"min_preload_n", "N", "attach condition: compressive contact force on the pad",
              Range::NonNegative()},
             &min_preload_n);
    a->Visit(
        {"initial_fraction", "", "bonded fraction at attach (centre-out)", Range::Closed(0, 1)},
        &initial_fraction);
    a->Visit({"buildup_time_s", "s",
              "time constant of the growth of the bonded fraction towards 1 while the pad is not "
              "pulled; 0: full at once",
              Range::NonNegative()},
             &buildup_time_s);
    a->Visit({"attach_window_s", "s",
              "after touchdown, how long contacts and preload may take to meet their conditions "
              "before the attach is rejected",
              Range::NonNegative()},
             &attach_window_s);
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
               "direction (adhesion.frictional)"},
              &law, {"von_mises", "frictional"});
    a->Visit({"frictional", "", "the frictional law's parameters (law: frictional)"}, &frictional);
    a->Visit({"release_contact_delay_s", "s",
              "model bonds: a pad let go by its release (detach cause released) collides again "
              "only this much later, so that it is not pushed out of the depth its landing pressed "
              "it to (a kick the other pads feel); 0 = at once",
              Range::NonNegative()},
             &release_contact_delay_s);
  }

  void Validate(const Checker& c) const {
    if (static_cast<long>(min_bonds) > static_cast<long>(grid_x) * grid_y) {
      c.Fail("min_bonds", "must be <= grid_x * grid_y = " + std::to_string(grid_x * grid_y) +
                              ", got " + std::to_string(min_bonds));
    }
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SCENARIO_ADHESION_KEYS_H_
