// One default per parameter: the default that `climbsim keys` documents for a scenario key
// (docs/scenario.md is made from it) is the default of the library struct that the key sets,
// read here from default-constructed library structs (cpg, reflex, adhesion), never from the
// scenario's own structs. A default changed in one place only fails here.
#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>

#include "adhesion/adhesion.h"
#include "cpg/cpg.h"
#include "reflex/reflex.h"
#include "tests/common/test_util.h"

namespace {

using climbsim::testing::CliResult;
using climbsim::testing::RunClimbsim;

// As the key table prints numbers (operator<< with the stream's defaults).
std::string Text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
std::string Text(int v) { return std::to_string(v); }
std::string Text(bool v) { return v ? "true" : "false"; }

// key -> documented default, from `climbsim keys` ("| `key` | unit | default | ... |").
std::map<std::string, std::string> DocumentedDefaults() {
  const CliResult r = RunClimbsim("keys");
  EXPECT_EQ(r.code, 0) << r.err;
  std::map<std::string, std::string> defaults;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const size_t key_end = line.find('`', 3);
    std::string cells = line.substr(key_end + 1);
    // cells: " | unit | default | allowed | meaning |"
    std::istringstream row(cells);
    std::string skip, unit, def;
    std::getline(row, skip, '|');
    std::getline(row, unit, '|');
    std::getline(row, def, '|');
    const size_t a = def.find_first_not_of(' '), b = def.find_last_not_of(' ');
    defaults[line.substr(3, key_end - 3)] = a == std::string::npos ? "" : def.substr(a, b - a + 1);
  }
  return defaults;
}

// Every scenario key that sets a library parameter, with the library's default.
std::map<std::string, std::string> LibraryDefaults() {
  namespace adhesion = climbsim::adhesion;
  namespace cpg = climbsim::cpg;
  namespace reflex = climbsim::reflex;
  const adhesion::PadParams pad;
  const adhesion::AttachParams attach;
  const adhesion::AdhesionSystemParams system;
  const adhesion::StickyPadParams sticky;
  const cpg::PhaseNetworkParams phase;
  const cpg::StepperParams stepper;
  const cpg::HopfNetworkParams hopf;
  const cpg::LegShape shape;
  const reflex::LegReflexParams leg;
  const reflex::LoadSharingParams share;
  const reflex::PostureParams posture;
  const reflex::TailReflexParams tail;
  return {
      {"adhesion.grid_x", Text(pad.grid_x)},
      {"adhesion.grid_y", Text(pad.grid_y)},
      {"adhesion.sigma_t_pa", Text(pad.sigma_t_pa)},
      {"adhesion.mu", Text(pad.mu)},
      {"adhesion.min_bonds", Text(pad.min_bonds)},
      {"adhesion.min_contacts", Text(attach.min_contacts)},
      {"adhesion.max_approach_speed_mps", Text(attach.max_approach_speed_mps)},
      {"adhesion.max_approach_angle_deg", Text(attach.max_approach_angle_deg)},
      {"adhesion.min_preload_n", Text(attach.min_preload_n)},
      {"adhesion.initial_fraction", Text(attach.initial_fraction)},
      {"adhesion.buildup_time_s", Text(attach.buildup_time_s)},
      {"adhesion.attach_window_s", Text(attach.attach_window_s)},
      {"adhesion.start_attached", Text(system.start_attached)},
      {"adhesion.start_gap_m", Text(system.start_gap_m)},
      {"adhesion.reach_m", Text(system.reach_m)},
      {"adhesion.ctrl", Text(sticky.actuator_ctrl)},
      {"adhesion.weld_solref", "[" + Text(adhesion::kDefaultWeldSolref[0]) + ", " +
                                   Text(adhesion::kDefaultWeldSolref[1]) + "]"},
      {"cpg.frequency_hz", Text(phase.frequency_hz)},
      {"cpg.amplitude_rate_per_s", Text(phase.amplitude_rate_per_s)},
      {"cpg.abs_tol", Text(stepper.abs_tol)},
      {"cpg.rel_tol", Text(stepper.rel_tol)},
      {"cpg.lift_share", Text(shape.lift_share)},
      {"cpg.hopf.mu", Text(hopf.mu)},
      {"cpg.hopf.alpha_per_s", Text(hopf.alpha_per_s)},
      {"cpg.hopf.beta_per_s", Text(hopf.beta_per_s)},
      {"cpg.hopf.switch_sharpness", Text(hopf.b)},
      {"reflex.max_offset_rad", Text(leg.max_offset_rad)},
      {"reflex.preload.enabled", Text(leg.preload.enabled)},
      {"reflex.preload.hip_pitch_press_rad", Text(leg.preload.hip_pitch_press_rad)},
      {"reflex.preload.knee_press_rad", Text(leg.preload.knee_press_rad)},
      {"reflex.preload.ramp_s", Text(leg.preload.ramp_s)},
      {"reflex.preload.force_limit_n", Text(leg.preload.force_limit_n)},
      {"reflex.preload.max_duration_s", Text(leg.preload.max_duration_s)},
      {"reflex.preload.release_s", Text(leg.preload.release_s)},
      {"reflex.preload.retry_gain", Text(leg.preload.retry_gain)},
      {"reflex.preload.retry_max_scale", Text(leg.preload.retry_max_scale)},
      {"reflex.preload.press_awaited_bond", Text(leg.preload.press_awaited_bond)},
      {"reflex.search.enabled", Text(leg.search.enabled)},
      {"reflex.search.reach_yaw_rad", Text(leg.search.reach_yaw_rad)},
      {"reflex.search.reach_pitch_rad", Text(leg.search.reach_pitch_rad)},
      {"reflex.search.reach_knee_rad", Text(leg.search.reach_knee_rad)},
      {"reflex.search.lift_rad", Text(leg.search.lift_rad)},
      {"reflex.search.attempt_duration_s", Text(leg.search.attempt_duration_s)},
      {"reflex.search.max_attempts", Text(leg.search.max_attempts)},
      {"reflex.search.release_s", Text(leg.search.release_s)},
      {"reflex.search.again_when_stood", Text(leg.search.again_when_stood)},
      {"reflex.peel.enabled", Text(leg.peel.enabled)},
      {"reflex.peel.hip_yaw_rad", Text(leg.peel.hip_yaw_rad)},
      {"reflex.peel.hip_pitch_lift_rad", Text(leg.peel.hip_pitch_lift_rad)},
      {"reflex.peel.knee_lift_rad", Text(leg.peel.knee_lift_rad)},
      {"reflex.peel.ramp_s", Text(leg.peel.ramp_s)},
      {"reflex.peel.max_duration_s", Text(leg.peel.max_duration_s)},
      {"reflex.peel.release_s", Text(leg.peel.release_s)},
      {"reflex.peel.active_release", Text(leg.peel.active_release)},
      {"reflex.peel.release_load_n", Text(leg.peel.release_load_n)},
      {"reflex.peel.wait_for_support", Text(leg.peel.wait_for_support)},
      {"reflex.regrip.enabled", Text(leg.regrip.enabled)},
      {"reflex.regrip.hold_others_s", Text(leg.regrip.hold_others_s)},
      {"reflex.regrip.lift_rad", Text(leg.regrip.lift_rad)},
      {"reflex.regrip.replace_s", Text(leg.regrip.replace_s)},
      {"reflex.regrip.replace_after_s", Text(leg.regrip.replace_after_s)},
      {"reflex.regrip.shift_rad", Text(leg.regrip.shift_rad)},
      {"reflex.regrip.shift_approach_refusals", Text(leg.regrip.shift_approach_refusals)},
      {"reflex.regrip.min_touched_share", Text(leg.regrip.min_touched_share)},
      {"reflex.regrip.partial_replaces", Text(leg.regrip.partial_replaces)},
      {"reflex.gto.enabled", Text(leg.gto.enabled)},
      {"reflex.gto.hold_gain_rad_per_n", Text(leg.gto.hold.gain)},
      {"reflex.gto.hold_threshold_n", Text(leg.gto.hold.threshold)},
      {"reflex.gto.hold_delay_s", Text(leg.gto.hold.delay_s)},
      {"reflex.gto.hold_max_offset_rad", Text(leg.gto.hold_max_offset_rad)},
      {"reflex.gto.count_compression", Text(leg.gto.count_compression)},
      {"reflex.gto.load_attached", Text(leg.gto.load_attached)},
      {"reflex.gto.press_gain_rad_per_n", Text(leg.gto.press.gain)},
      {"reflex.gto.press_threshold_n", Text(leg.gto.press.threshold)},
      {"reflex.gto.press_delay_s", Text(leg.gto.press.delay_s)},
      {"reflex.gto.press_max_offset_rad", Text(leg.gto.press_max_offset_rad)},
      {"reflex.gto.full_bond_fraction", Text(leg.gto.full_bond_fraction)},
      {"reflex.gto.require_partner_attached", Text(leg.gto.require_partner_attached)},
      {"reflex.gto.unload_gain", Text(leg.gto.unload.gain)},
      {"reflex.gto.unload_threshold", Text(leg.gto.unload.threshold)},
      {"reflex.gto.unload_delay_s", Text(leg.gto.unload.delay_s)},
      {"reflex.gto.unload_min_kp_fraction", Text(leg.gto.unload_min_kp_fraction)},
      {"reflex.gto.support_threshold", Text(leg.gto.support.threshold)},
      {"reflex.gto.support_delay_s", Text(leg.gto.support.delay_s)},
      {"reflex.gto.share.mode",
       share.mode == reflex::SharingMode::kUtilisation ? "utilisation" : "force_tracking"},
      {"reflex.gto.share.gain_per_s", Text(share.gain_per_s)},
      {"reflex.gto.share.threshold", Text(share.threshold)},
      {"reflex.gto.share.leak_s", Text(share.leak_s)},
      {"reflex.gto.share.softmax_beta", Text(share.softmax_beta)},
      {"reflex.gto.share.max_force_n", Text(share.max_force_n)},
      {"reflex.gto.share.max_rate_n_per_s", Text(share.max_rate_n_per_s)},
      {"reflex.gto.share.period_s", Text(share.period_s)},
      {"reflex.gto.posture.enabled", Text(posture.enabled)},
      {"reflex.gto.posture.gain_m", Text(posture.pull.gain)},
      {"reflex.gto.posture.threshold", Text(posture.pull.threshold)},
      {"reflex.gto.posture.delay_s", Text(posture.pull.delay_s)},
      {"reflex.gto.posture.max_crouch_m", Text(posture.max_crouch_m)},
      {"reflex.gto.posture.time_constant_s", Text(posture.time_constant_s)},
      {"reflex.spindle.enabled", Text(leg.spindle.enabled)},
      {"reflex.spindle.swing_threshold_rad", Text(leg.spindle.swing_threshold_rad)},
      {"reflex.spindle.resist", Text(leg.spindle.resist)},
      {"reflex.spindle.stance_band_rad", Text(leg.spindle.stance_band_rad)},
      {"reflex.spindle.hold_s", Text(leg.spindle.hold_s)},
      {"reflex.spindle.max_hold_s", Text(leg.spindle.max_hold_s)},
      {"reflex.spindle.length_gain", Text(reflex::SpindleParams{}.length_gain)},
      {"reflex.spindle.velocity_gain_s", Text(reflex::SpindleParams{}.velocity_gain_s)},
      {"reflex.spindle.length_threshold_rad", Text(reflex::SpindleParams{}.length_threshold_rad)},
      {"reflex.spindle.velocity_threshold_rad_per_s",
       Text(reflex::SpindleParams{}.velocity_threshold_rad_per_s)},
      {"reflex.spindle.delay_s", Text(reflex::SpindleParams{}.delay_s)},
      {"reflex.compliance.enabled", Text(leg.compliance.enabled)},
      {"reflex.compliance.stance_kp_fraction", Text(leg.compliance.stance_kp_fraction)},
      {"reflex.compliance.ramp_s", Text(leg.compliance.ramp_s)},
      {"reflex.tail.rest_rad", Text(tail.rest_rad)},
      {"reflex.tail.press_rad", Text(tail.press_rad)},
      {"reflex.tail.on_front_pad_loss", Text(tail.on_front_pad_loss)},
      {"reflex.tail.pitch_threshold_rad", Text(tail.pitch_threshold_rad)},
      {"reflex.tail.delay_s", Text(tail.delay_s)},
      {"reflex.tail.hold_s", Text(tail.hold_s)},
      {"reflex.tail.ease_s", Text(tail.ease_s)},
      {"reflex.tail.yaw_rad", Text(tail.yaw_rad)},
  };
}

TEST(KeysDefaults, EveryLibraryParameterKeyDocumentsTheLibrarysDefault) {
  const std::map<std::string, std::string> documented = DocumentedDefaults();
  ASSERT_GT(documented.size(), 100u) << "`climbsim keys` printed too few rows";
  for (const auto& [key, library] : LibraryDefaults()) {
    const auto it = documented.find(key);
    ASSERT_NE(it, documented.end()) << key << " is not a scenario key any more";
    EXPECT_EQ(it->second, library) << key << ": `climbsim keys` documents " << it->second
                                   << ", the library's default is " << library;
  }
}

// Every reflex key but the scenario's own (below) is a parameter of the reflex module: none is
// left out of the comparison above.
TEST(KeysDefaults, EveryReflexKeyIsComparedWithTheReflexModule) {
  const std::map<std::string, std::string> documented = DocumentedDefaults();
  const std::map<std::string, std::string> library = LibraryDefaults();
  for (const auto& [key, def] : documented) {
    if (key.rfind("reflex.", 0) != 0) continue;
    if (def == "(map)" || def == "(absent: off)") continue;  // a block, not a parameter
    if (key == "reflex.release_failed_peel") continue;  // the scenario's own: what sim does
    if (key == "reflex.peel.against_grip") continue;    // the scenario's own: signs per pad
    // The scenario's own: force tracking's targets and the landing act on MuJoCo's pads and
    // Jacobians (sim/reflex_effect.cc), not in the reflex module.
    if (key == "reflex.gto.share.friction_credit") continue;
    if (key == "reflex.gto.share.min_grip_n") continue;
    if (key.rfind("reflex.landing.", 0) == 0) continue;
    EXPECT_TRUE(library.count(key)) << key << " has no library default in this test";
  }
}

}  // namespace
