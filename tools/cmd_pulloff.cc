// climbsim pulloff --out DIR [options]: the seed's figure-6 experiment in MuJoCo
// (adhesion/pulloff_rig.h) for this project's bond model and MuJoCo's adhesion actuator, with
// the quasi-static results of adhesion/pulloff.h, written to DIR/pulloff.csv and plotted to
// DIR/pulloff.png (the gnuplot script is kept as DIR/pulloff.gp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>

#include "adhesion/adhesion.h"
#include "common/common.h"
#include "sim/sim.h"
#include "tools/commands.h"
#include "tools/pulloff_law.h"

namespace climbsim::tools {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The options: the rig's and the sweep's own parameters (their defaults are the library's),
// and what only the command has.
struct PulloffOptions {
  std::string out_dir;
  std::string model = "both";
  adhesion::PulloffRigParams rig;
  adhesion::SweepRange range;
  std::optional<double> length_m;  // default: the width
  int grid = 0;                    // > 0 sets both sides
  double azimuth_deg = 0.0;        // rig.azimuth_rad in degrees
  bool quiet = false;
  bool force = false;
  std::string law = "von_mises";  // frictional: tools/pulloff_law.h
  adhesion::FrictionalParams frictional;
  double grip_deg = 0.0;
};

struct Row {
  double angle_deg = 0.0;
  adhesion::PulloffRun bonds, mujoco;
  double quasi_static_n = 0.0;
  double closed_form_n = std::numeric_limits<double>::quiet_NaN();
  double mujoco_closed_n = 0.0;
};

// "inf" for a pad that never let go, "" for a column that does not apply.
std::string Num(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return "inf";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string Csv(const std::vector<Row>& rows, bool bonds, bool mujoco, double capacity_n) {
  std::string out =
      "angle_deg,force_n,cause,bond_loss_steps,mujoco_force_n,mujoco_cause,quasi_static_n,"
      "closed_form_n,mujoco_closed_form_n,capacity_n\n";
  for (const Row& r : rows) {
    std::ostringstream line;
    line << Num(r.angle_deg) << ',' << (bonds ? Num(r.bonds.force_n) : "") << ','
         << (bonds ? r.bonds.cause : "") << ','
         << (bonds ? std::to_string(r.bonds.steps_losing_bonds) : "") << ','
         << (mujoco ? Num(r.mujoco.force_n) : "") << ',' << (mujoco ? r.mujoco.cause : "") << ','
         << Num(r.quasi_static_n) << ',' << Num(r.closed_form_n) << ',' << Num(r.mujoco_closed_n)
         << ',' << Num(capacity_n) << '\n';
    out += line.str();
  }
  return out;
}

// The gnuplot script; `data` and `output` are gnuplot string literals.
std::string Script(const PulloffOptions& o, const std::string& data, const std::string& output,
                   bool bonds, bool mujoco, double capacity_n, double y_max) {
  const adhesion::PadParams& pad = o.rig.pad;
  char title[256];
  std::snprintf(title, sizeof(title),
                "Pull-off of a weightless block: %g x %g mm pad, %d x %d bonds, sigma_T %g kPa, "
                "mu %g, lever %g mm",
                pad.width_m * 1e3, pad.length_m * 1e3, pad.grid_x, pad.grid_y,
                pad.sigma_t_pa * 1e-3, pad.mu, o.rig.arm_m * 1e3);
  std::ostringstream s;
  s << "set terminal pngcairo size 900,600 font \",11\"\n"
    << "set output " << output << "\n"
    << "set datafile separator \",\"\n"
    << "set title " << common::GnuplotQuote(title) << "\n"
    << "set xlabel \"pull angle from the surface normal (deg): 0 pulls off, 90 shears, "
       "180 pushes\"\n"
    << "set ylabel \"pull-off force / (sigma_T A)\"\n"
    << "set xrange [" << o.range.from_deg << ":" << o.range.to_deg << "]\n"
    << "set yrange [0:" << y_max << "]\n"
    << "set xtics 15\nset grid\nset key top left\n"
    << "cap = " << capacity_n << "\n"
    << "plot ";
  std::vector<std::string> curves;
  if (bonds) {
    curves.push_back(data +
                     " using 1:($2/cap) skip 1 with linespoints lw 2 pt 7 ps 0.6 "
                     "lc rgb \"#c0392b\" title \"bond model in MuJoCo (weld + bond grid)\"");
  }
  curves.push_back(data +
                   " using 1:($7/cap) skip 1 with lines dt 2 lw 2 lc rgb \"#e67e22\" "
                   "title \"bond model, quasi-static (pulloff.h)\"");
  if (o.rig.arm_m == 0.0) {
    curves.push_back(data +
                     " using 1:($8/cap) skip 1 with lines dt 3 lw 1.5 lc rgb \"#555555\" "
                     "title \"closed form (fine grid)\"");
  }
  if (mujoco) {
    curves.push_back(data +
                     " using 1:($5/cap) skip 1 with linespoints lw 2 pt 5 ps 0.6 "
                     "lc rgb \"#2471a3\" title \"MuJoCo adhesion actuator\"");
    curves.push_back(data +
                     " using 1:($9/cap) skip 1 with lines dt 3 lw 1.5 lc rgb \"#5dade2\" "
                     "title \"actuator: lift/tip/slide closed form\"");
  }
  for (size_t i = 0; i < curves.size(); ++i) s << (i ? ", \\\n     " : "") << curves[i];
  s << "\n";
  return s.str();
}

void Check(bool ok, const std::string& option, const std::string& message) {
  if (!ok) throw CLI::ValidationError(option, message);
}

void Run(PulloffOptions o) {
  adhesion::PulloffRigParams& p = o.rig;
  p.pad.length_m = o.length_m.value_or(p.pad.width_m);
  if (o.grid > 0) p.pad.grid_x = p.pad.grid_y = o.grid;
  if (o.law == "frictional") {  // both laws quasi-static on one plot (tools/pulloff_law.h)
    Check(o.range.from_deg <= o.range.to_deg, "--from-deg", "must be <= --to-deg");
    Check(p.pad.min_bonds <= p.pad.grid_x * p.pad.grid_y, "--min-bonds",
          "must be <= grid_x * grid_y");
    PulloffLawOptions l;
    l.out_dir = o.out_dir, l.force = o.force, l.quiet = o.quiet;
    l.pad = p.pad;
    l.law = o.frictional;
    l.law.grip_x = std::cos(o.grip_deg * kDeg);
    l.law.grip_y = std::sin(o.grip_deg * kDeg);
    l.arm_m = p.arm_m;
    l.from_deg = o.range.from_deg, l.to_deg = o.range.to_deg, l.step_deg = o.range.step_deg;
    l.max_force_factor = p.max_force_factor;
    RunPulloffLaws(l);
    return;
  }
  p.azimuth_rad = o.azimuth_deg * kDeg;
  Check(o.range.from_deg <= o.range.to_deg, "--from-deg", "must be <= --to-deg");
  Check(p.pad.min_bonds <= p.pad.grid_x * p.pad.grid_y, "--min-bonds",
        "must be <= grid_x * grid_y");
  const bool bonds = o.model != "mujoco", mujoco = o.model != "bonds";
  std::vector<double> angles_deg;
  try {
    adhesion::ValidatePulloffRigParams(p);
    angles_deg = adhesion::SweepAnglesDeg(o.range);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("pulloff", e.what());
  }

  // The output folder: checked and locked before anything runs; it appears whole.
  sim::RunFolder folder(o.out_dir, {.made_by = "pulloff", .force = o.force});
  const std::string dir = folder.path();

  std::vector<Row> rows(angles_deg.size());
  for (size_t k = 0; k < rows.size(); ++k) rows[k].angle_deg = angles_deg[k];

  // Both rigs are compiled here (MuJoCo's loader is not thread-safe), then each model sweeps
  // on its own thread.
  std::unique_ptr<adhesion::PulloffRig> bond_rig, mujoco_rig;
  if (bonds) bond_rig = std::make_unique<adhesion::PulloffRig>(adhesion::AdhesionModel::kBonds, p);
  if (mujoco) {
    mujoco_rig = std::make_unique<adhesion::PulloffRig>(adhesion::AdhesionModel::kMujoco, p);
  }
  const double capacity = p.pad.sigma_t_pa * p.pad.width_m * p.pad.length_m;
  const double gain = p.gain_n > 0 ? p.gain_n : capacity;
  const auto started = std::chrono::steady_clock::now();
  std::thread mujoco_thread([&] {
    if (!mujoco_rig) return;
    for (Row& r : rows) r.mujoco = mujoco_rig->Run(r.angle_deg * kDeg);
  });
  for (Row& r : rows) {
    const double theta = r.angle_deg * kDeg;
    if (bond_rig) r.bonds = bond_rig->Run(theta);
    adhesion::PullSetup setup{.angle_rad = theta, .azimuth_rad = p.azimuth_rad, .arm_m = p.arm_m};
    adhesion::PulloffOptions qs;
    qs.max_force_factor = p.max_force_factor;
    const adhesion::PulloffResult q = adhesion::PullOff(p.pad, setup, qs);
    r.quasi_static_n = q.force_n;
    if (p.arm_m == 0.0) {
      r.closed_form_n = capacity * adhesion::CentralPulloffPerCapacity(theta, p.pad.mu);
    }
    r.mujoco_closed_n =
        adhesion::MujocoPulloffClosedForm(gain, p.friction, p.pad.width_m, p.arm_m, theta);
  }
  mujoco_thread.join();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();

  // Files: the CSV and the script first, then the plot.
  const std::string csv_path = dir + "/pulloff.csv";
  const std::string png_path = dir + "/pulloff.png";
  common::WriteFileAtomic(csv_path, Csv(rows, bonds, mujoco, capacity));
  double y_max = 0.0;
  for (const Row& r : rows) {
    for (double f :
         {bonds ? r.bonds.force_n : 0.0, mujoco ? r.mujoco.force_n : 0.0, r.quasi_static_n}) {
      if (std::isfinite(f)) y_max = std::max(y_max, f / capacity);
    }
  }
  y_max = std::min(3.0, std::ceil(1.1 * y_max * 4.0) / 4.0);
  common::WriteFileAtomic(
      dir + "/pulloff.gp",
      "# cd into this folder and run: gnuplot pulloff.gp\n" +
          Script(o, "\"pulloff.csv\"", "\"pulloff.png\"", bonds, mujoco, capacity, y_max));
  const std::string error = common::RunGnuplot(
      Script(o, common::GnuplotQuote(csv_path), "OUTPUT(0)", bonds, mujoco, capacity, y_max),
      {png_path});
  folder.Commit();

  if (!o.quiet) {
    std::printf("climbsim pulloff: %zu angles in %.2f s; sigma_T*A = %.4g N\n", rows.size(), wall_s,
                capacity);
    std::printf("%9s %11s %11s %8s %11s %11s %9s\n", "angle_deg", "bonds_n", "quasi_st_n", "diff_%",
                "mujoco_n", "mj_closed_n", "diff_%");
    for (const Row& r : rows) {
      const double d1 = 100.0 * (r.bonds.force_n / r.quasi_static_n - 1.0);
      const double d2 = 100.0 * (r.mujoco.force_n / r.mujoco_closed_n - 1.0);
      std::printf("%9g %11s %11s %8s %11s %11s %9s\n", r.angle_deg,
                  bonds ? Num(r.bonds.force_n).c_str() : "-", Num(r.quasi_static_n).c_str(),
                  bonds && std::isfinite(d1) ? Num(d1).c_str() : "-",
                  mujoco ? Num(r.mujoco.force_n).c_str() : "-", Num(r.mujoco_closed_n).c_str(),
                  mujoco && std::isfinite(d2) ? Num(d2).c_str() : "-");
    }
    std::printf("  outputs %s/{pulloff.csv,pulloff.gp%s}\n", o.out_dir.c_str(),
                error.empty() ? ",pulloff.png" : "");
  }
  if (!error.empty()) {
    std::fprintf(stderr, "climbsim pulloff: no plot: %s\n", error.c_str());
    ExitCode() = 1;
  }
}

}  // namespace

void AddPulloffCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "pulloff",
      "The seed's figure-6 experiment in MuJoCo: the force that pulls a weightless sticky block "
      "off a plane, against the pull angle, for the bond model and MuJoCo's adhesion actuator");
  static PulloffOptions o;
  cmd->add_option("--out", o.out_dir,
                  "folder for pulloff.csv, pulloff.gp and pulloff.png: new, empty, or (with "
                  "--force) an earlier climbsim folder (docs/run-folders.md)")
      ->required();
  cmd->add_flag("--force", o.force, "replace the earlier climbsim folder at --out whole");
  cmd->add_option("--model", o.model, "which model to run: both, bonds or mujoco")
      ->check(CLI::IsMember({"both", "bonds", "mujoco"}))
      ->capture_default_str();
  cmd->add_option("--width-m", o.rig.pad.width_m, "pad width b (m), along x")
      ->check(CLI::Range(1e-4, 1.0))
      ->capture_default_str();
  cmd->add_option("--length-m", o.length_m, "pad length h (m), along y; default: the width")
      ->check(CLI::Range(1e-4, 1.0));
  cmd->add_option("--grid", o.grid, "bonds per side (sets --grid-x and --grid-y)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--grid-x", o.rig.pad.grid_x, "bonds across the width")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  cmd->add_option("--grid-y", o.rig.pad.grid_y, "bonds along the length")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  cmd->add_option("--sigma-t-pa", o.rig.pad.sigma_t_pa, "rupture threshold sigma_T (Pa)")
      ->check(CLI::Range(1e-3, 1e12))
      ->capture_default_str();
  cmd->add_option("--mu", o.rig.pad.mu, "gain of compression on the shear threshold (>= 0)")
      ->check(CLI::Range(0.0, 1e3))
      ->capture_default_str();
  cmd->add_option("--min-bonds", o.rig.pad.min_bonds, "the pad detaches below this many bonds")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  cmd->add_option("--arm-m", o.rig.arm_m, "lever: height of the pull point above the pad face (m)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--azimuth-deg", o.azimuth_deg,
                  "direction of the pull's in-plane part, from +x towards +y (deg)")
      ->check(CLI::Range(-360.0, 360.0))
      ->capture_default_str();
  cmd->add_option("--from-deg", o.range.from_deg, "first pull angle (deg from the surface normal)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->add_option("--to-deg", o.range.to_deg, "last pull angle (deg)")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->add_option("--step-deg", o.range.step_deg, "angle step (deg)")
      ->check(CLI::Range(0.01, 180.0))
      ->capture_default_str();
  cmd->add_option("--ramp-time-s", o.rig.ramp_time_s,
                  "time for the pull to rise to sigma_T*A (s): slower is more quasi-static")
      ->check(CLI::Range(1e-3, 1e3))
      ->capture_default_str();
  cmd->add_option("--timestep-s", o.rig.timestep_s, "MuJoCo time step (s)")
      ->check(CLI::Range(1e-5, 0.01))
      ->capture_default_str();
  cmd->add_option("--gain-n", o.rig.gain_n,
                  "MuJoCo adhesion-actuator gain (N); default sigma_T times the pad area")
      ->check(CLI::Range(0.0, 1e9));
  cmd->add_option("--friction", o.rig.friction, "pad friction for the actuator model")
      ->check(CLI::Range(1e-3, 10.0))
      ->capture_default_str();
  cmd->add_option("--max-force-factor", o.rig.max_force_factor,
                  "stop pulling at this many sigma_T*A: the block never lets go (written inf)")
      ->check(CLI::Range(1.01, 1e3))
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
      ->check(CLI::Range(0.01, 89.99))
      ->capture_default_str();
  cmd->add_option("--shear-limit-pa", o.frictional.shear_limit_pa,
                  "frictional: shear limit tau_max (Pa); F_t,max = tau_max * A")
      ->check(CLI::Range(1e-3, 1e12))
      ->capture_default_str();
  cmd->add_option("--friction-mu", o.frictional.friction_mu,
                  "frictional: Coulomb friction of a pressed pad")
      ->check(CLI::Range(0.0, 1e3))
      ->capture_default_str();
  cmd->add_option("--grip-deg", o.grip_deg,
                  "frictional: gripping direction in the pad plane, from +x towards +y (deg)")
      ->check(CLI::Range(-360.0, 360.0))
      ->capture_default_str();
  cmd->footer(
      "pulloff.csv: angle_deg, force_n (bond model in MuJoCo), cause (peel or overload),\n"
      "  bond_loss_steps, mujoco_force_n, mujoco_cause (lift, tip or slide), quasi_static_n\n"
      "  (adhesion/pulloff.h on the same grid), closed_form_n (central pull, fine grid),\n"
      "  mujoco_closed_form_n, capacity_n (sigma_T*A); inf: the block never let go.\n"
      "Example:\n  climbsim pulloff --out runs/pulloff --grid 16 --arm-m 0.005");
  cmd->callback([] { Run(o); });
}

}  // namespace climbsim::tools
