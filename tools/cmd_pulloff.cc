// climbsim pulloff --out DIR [options]: the command line of the pull-off experiment
// (optimise/pulloff.cc runs it).
#include <optional>
#include <string>

#include "experiments/experiments.h"
#include "tools/commands.h"

namespace climbsim::tools {

void AddPulloffCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "pulloff",
      "The seed's figure-6 experiment in MuJoCo: the force that pulls a weightless sticky block "
      "off a plane, against the pull angle, for the bond model and MuJoCo's adhesion actuator");
  static optimise::PulloffExperimentOptions o;
  cmd->add_option("--out", o.out_dir,
                  "folder for pulloff.csv, pulloff.gp and pulloff.png: new, empty, or (with "
                  "--force) an earlier climbsim folder (docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", o.force,
                "replace the earlier climbsim folder at --out (deleting only its own files)");
  cmd->add_flag("--keep-other-files", o.keep_other_files,
                "with --force: carry files climbsim did not write (notes, added folders) into "
                "the new run folder instead of refusing (docs/run-folders.md)");
  cmd->add_option("--model", o.model, "which model to run: both, bonds or mujoco")
      ->check(CLI::IsMember({"both", "bonds", "mujoco"}))
      ->capture_default_str();
  cmd->add_option("--width-m", o.rig.pad.width_m, "pad width b (m), along x")
      ->check(InRange(optimise::kPadWidthRangeM))
      ->capture_default_str();
  cmd->add_option("--length-m", o.length_m, "pad length h (m), along y; default: the width")
      ->check(InRange(optimise::kPadWidthRangeM));
  cmd->add_option("--grid", o.grid, "bonds per side (sets --grid-x and --grid-y)")
      ->check(InRange(optimise::kGridRange));
  cmd->add_option("--grid-x", o.rig.pad.grid_x, "bonds across the width")
      ->check(InRange(optimise::kGridRange))
      ->capture_default_str();
  cmd->add_option("--grid-y", o.rig.pad.grid_y, "bonds along the length")
      ->check(InRange(optimise::kGridRange))
      ->capture_default_str();
  cmd->add_option("--sigma-t-pa", o.rig.pad.sigma_t_pa, "rupture threshold sigma_T (Pa)")
      ->check(InRange(optimise::kSigmaTRangePa))
      ->capture_default_str();
  cmd->add_option("--mu", o.rig.pad.mu, "gain of compression on the shear threshold (>= 0)")
      ->check(InRange(optimise::kMuRange))
      ->capture_default_str();
  cmd->add_option("--min-bonds", o.rig.pad.min_bonds, "the pad detaches below this many bonds")
      ->check(InRange(optimise::kMinBondsRange))
      ->capture_default_str();
  cmd->add_option("--arm-m", o.rig.arm_m, "lever: height of the pull point above the pad face (m)")
      ->check(InRange(optimise::kArmRangeM))
      ->capture_default_str();
  cmd->add_option("--azimuth-deg", o.azimuth_deg,
                  "direction of the pull's in-plane part, from +x towards +y (deg)")
      ->check(InRange(optimise::kAzimuthRangeDeg))
      ->capture_default_str();
  cmd->add_option("--from-deg", o.range.from_deg, "first pull angle (deg from the surface normal)")
      ->check(InRange(optimise::kPullAngleRangeDeg))
      ->capture_default_str();
  cmd->add_option("--to-deg", o.range.to_deg, "last pull angle (deg)")
      ->check(InRange(optimise::kPullAngleRangeDeg))
      ->capture_default_str();
  cmd->add_option("--step-deg", o.range.step_deg, "angle step (deg)")
      ->check(InRange(optimise::kStepRangeDeg))
      ->capture_default_str();
  cmd->add_option("--ramp-time-s", o.rig.ramp_time_s,
                  "time for the pull to rise to sigma_T*A (s): slower is more quasi-static")
      ->check(InRange(optimise::kRampTimeRangeS))
      ->capture_default_str();
  cmd->add_option("--timestep-s", o.rig.timestep_s, "MuJoCo time step (s)")
      ->check(InRange(optimise::kTimestepRangeS))
      ->capture_default_str();
  cmd->add_option("--gain-n", o.rig.gain_n,
                  "MuJoCo adhesion-actuator gain (N); default sigma_T times the pad area")
      ->check(InRange(optimise::kGainRangeN));
  cmd->add_option("--friction", o.rig.friction, "pad friction for the actuator model")
      ->check(InRange(optimise::kFrictionRange))
      ->capture_default_str();
  cmd->add_option("--max-force-factor", o.rig.max_force_factor,
                  "stop pulling at this many sigma_T*A: the block never lets go (written inf)")
      ->check(InRange(optimise::kMaxForceFactorRange))
      ->capture_default_str();
  cmd->add_flag("--quiet", o.quiet, "no table on the terminal");
  cmd->add_option("--law", o.law,
                  "von_mises: the rigs above; frictional: the directional law beside von Mises, "
                  "quasi-static on the bond grid and in closed form: limit curve and pull-off "
                  "against angle on one plot (the pull's in-plane part along the grip, and "
                  "against it)")
      ->check(CLI::IsMember({"von_mises", "frictional"}))
      ->capture_default_str();
  cmd->add_option("--critical-angle-deg", o.frictional.critical_angle_deg,
                  "frictional: critical angle alpha* (deg)")
      ->check(InRange(optimise::kCriticalAngleRangeDeg))
      ->capture_default_str();
  cmd->add_option("--shear-limit-pa", o.frictional.shear_limit_pa,
                  "frictional: shear limit tau_max (Pa); F_t,max = tau_max * A")
      ->check(InRange(optimise::kShearLimitRangePa))
      ->capture_default_str();
  cmd->add_option("--friction-mu", o.frictional.friction_mu,
                  "frictional: Coulomb friction of a pressed pad")
      ->check(InRange(optimise::kFrictionMuRange))
      ->capture_default_str();
  cmd->add_option("--grip-deg", o.grip_deg,
                  "frictional: gripping direction in the pad plane, from +x towards +y (deg)")
      ->check(InRange(optimise::kAzimuthRangeDeg))
      ->capture_default_str();
  cmd->footer(
      "pulloff.csv: angle_deg, force_n (bond model in MuJoCo), cause (peel or overload),\n"
      "  bond_loss_steps, mujoco_force_n, mujoco_cause (lift, tip or slide), quasi_static_n\n"
      "  (adhesion/pulloff.h on the same grid), closed_form_n (central pull, fine grid),\n"
      "  mujoco_closed_form_n, capacity_n (sigma_T*A); inf: the block never let go.\n"
      "Example:\n  climbsim pulloff --out runs/pulloff --grid 16 --arm-m 0.005");
  cmd->callback([] {
    if (!optimise::RunPulloffExperiment(o)) ExitCode() = 1;
  });
}

}  // namespace climbsim::tools
