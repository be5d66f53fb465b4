// climbsim pulloff: the seed's figure-6 experiment in MuJoCo (adhesion/pulloff_rig.h) for this
// project's bond model and MuJoCo's adhesion actuator, with the quasi-static results of
// adhesion/pulloff.h, written to DIR/pulloff.csv and plotted to DIR/pulloff.png (the gnuplot
// script is kept as DIR/pulloff.gp); and, with the frictional law, both laws side by side.
#include <chrono>
#include <algorithm>
#include <vector>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>

#include "adhesion/adhesion.h"
#include "common/common.h"
#include "experiments/experiments.h"
#include "sim/sim.h"

namespace climbsim::optimise {
namespace {

constexpr double kDeg = M_PI / 180.0;


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

// The gnuplot script, run inside the output folder; `data` and `output` are gnuplot string
// literals of plain file names there.
std::string Script(const PulloffExperimentOptions& o, const std::string& data,
                   const std::string& output, bool bonds, bool mujoco, double capacity_n,
                   double y_max) {
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
  if (!ok) throw InputError(option, 0, 0, "", message);
}

}  // namespace

namespace {

// --law frictional: the quasi-static laws' options from the rig's.
PulloffLawOptions LawOptions(const PulloffExperimentOptions& o) {
  const adhesion::PulloffRigParams& p = o.rig;
  PulloffLawOptions l;
  l.out_dir = o.out_dir, l.force = o.force, l.quiet = o.quiet;
  l.keep_other_files = o.keep_other_files;
  l.pad = p.pad;
  l.law = o.frictional;
  l.law.grip_x = std::cos(o.grip_deg * kDeg);
  l.law.grip_y = std::sin(o.grip_deg * kDeg);
  l.arm_m = p.arm_m;
  l.from_deg = o.range.from_deg, l.to_deg = o.range.to_deg, l.step_deg = o.range.step_deg;
  l.max_force_factor = p.max_force_factor;
  return l;
}

// The rows at `angles_deg`: the MuJoCo rigs' runs and the quasi-static and closed-form
// forces. Both rigs are compiled here (MuJoCo's loader is not thread-safe), then each model
// sweeps on its own thread; an exception in either reaches the caller.
std::vector<Row> SweepRigs(const adhesion::PulloffRigParams& p,
                           const std::vector<double>& angles_deg, bool bonds, bool mujoco) {
  std::vector<Row> rows(angles_deg.size());
  for (size_t k = 0; k < rows.size(); ++k) rows[k].angle_deg = angles_deg[k];
  std::unique_ptr<adhesion::PulloffRig> bond_rig, mujoco_rig;
  if (bonds) bond_rig = std::make_unique<adhesion::PulloffRig>(adhesion::AdhesionModel::kBonds, p);
  if (mujoco) {
    mujoco_rig = std::make_unique<adhesion::PulloffRig>(adhesion::AdhesionModel::kMujoco, p);
  }
  const double capacity = p.pad.sigma_t_pa * p.pad.width_m * p.pad.length_m;
  const double gain = p.gain_n > 0 ? p.gain_n : capacity;
  // Task 1 sweeps the MuJoCo rig on a second thread.
  common::ParallelFor(2, 2, [&](int task) {
    if (task == 1) {
      if (!mujoco_rig) return;
      for (Row& r : rows) r.mujoco = mujoco_rig->Run(r.angle_deg * kDeg);
      return;
    }
    for (Row& r : rows) {
      const double theta = r.angle_deg * kDeg;
      if (bond_rig) r.bonds = bond_rig->Run(theta);
      adhesion::PullSetup setup{
          .angle_rad = theta, .azimuth_rad = p.azimuth_rad, .arm_m = p.arm_m};
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
  });
  return rows;
}

// pulloff.csv, pulloff.gp and pulloff.png in `dir`; returns why the plot is missing ("" when
// drawn).
std::string WriteRigFiles(const std::string& dir, const PulloffExperimentOptions& o,
                          const std::vector<Row>& rows, bool bonds, bool mujoco,
                          double capacity) {
  // The CSV and the script first, then the plot.
  common::WriteFileAtomic(dir + "/pulloff.csv", Csv(rows, bonds, mujoco, capacity));
  double y_max = 0.0;
  for (const Row& r : rows) {
    for (double f :
         {bonds ? r.bonds.force_n : 0.0, mujoco ? r.mujoco.force_n : 0.0, r.quasi_static_n}) {
      if (std::isfinite(f)) y_max = std::max(y_max, f / capacity);
    }
  }
  y_max = std::min(3.0, std::ceil(1.1 * y_max * 4.0) / 4.0);
  // pulloff.gp names no folder: a user runs it where it lies, as gnuplot runs it here.
  const std::string data = common::GnuplotQuote("pulloff.csv");
  common::WriteFileAtomic(
      dir + "/pulloff.gp",
      "# cd into this folder and run: gnuplot pulloff.gp\n" +
          Script(o, data, common::GnuplotQuote("pulloff.png"), bonds, mujoco, capacity, y_max));
  return common::RunGnuplot(
      dir, Script(o, data, "OUTPUT(0)", bonds, mujoco, capacity, y_max), {"pulloff.png"});
}

void PrintRigTable(const PulloffExperimentOptions& o, const std::vector<Row>& rows, bool bonds,
                   bool mujoco, double capacity, double wall_s, const std::string& error) {
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

}  // namespace

bool RunPulloffExperiment(PulloffExperimentOptions o) {
  adhesion::PulloffRigParams& p = o.rig;
  p.pad.length_m = o.length_m.value_or(p.pad.width_m);
  if (o.grid > 0) p.pad.grid_x = p.pad.grid_y = o.grid;
  Check(o.range.from_deg <= o.range.to_deg, "--from-deg", "must be <= --to-deg");
  Check(p.pad.min_bonds <= p.pad.grid_x * p.pad.grid_y, "--min-bonds",
        "must be <= grid_x * grid_y");
  // Both laws quasi-static on one plot.
  if (o.law == "frictional") return RunPulloffLaws(LawOptions(o));
  p.azimuth_rad = o.azimuth_deg * kDeg;
  const bool bonds = o.model != "mujoco", mujoco = o.model != "bonds";
  std::vector<double> angles_deg;
  // The adhesion module's checks name the parameter; "pulloff" says where it came from.
  try {
    adhesion::ValidatePulloffRigParams(p);
    angles_deg = adhesion::SweepAnglesDeg(o.range);
  } catch (const std::invalid_argument& e) {
    throw InputError("pulloff", 0, 0, "", e.what());
  }

  // The output folder: checked and locked before anything runs; it appears whole.
  sim::RunFolder folder(
      o.out_dir, {.made_by = "pulloff", .force = o.force, .keep_other_files = o.keep_other_files});
  const auto started = std::chrono::steady_clock::now();
  const std::vector<Row> rows = SweepRigs(p, angles_deg, bonds, mujoco);
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const double capacity = p.pad.sigma_t_pa * p.pad.width_m * p.pad.length_m;
  const std::string error = WriteRigFiles(folder.path(), o, rows, bonds, mujoco, capacity);
  folder.Commit();
  if (!o.quiet) PrintRigTable(o, rows, bonds, mujoco, capacity, wall_s, error);
  if (!error.empty()) std::fprintf(stderr, "climbsim pulloff: no plot: %s\n", error.c_str());
  return error.empty();
}

// ---- --law frictional ------------------------------------------------------------------

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct LawRow {
  double angle_deg = 0.0;
  double frictional_n = 0.0, frictional_closed_n = kNaN;
  double reversed_n = 0.0, reversed_closed_n = kNaN;
  double von_mises_n = 0.0, von_mises_closed_n = kNaN;
};


// A point of a limit curve: the pull-off vector (F_t, F_n) of a pull at θ, on the side
// `sign` (+1 along d, −1 against it); nothing for a pad that never lets go or a force beyond
// `clip_n`.
void Point(std::ostringstream* out, double force_n, double theta, double sign, double clip_n) {
  if (!std::isfinite(force_n) || force_n > clip_n) return;
  *out << Num(sign * force_n * std::sin(theta)) << ',' << Num(force_n * std::cos(theta)) << '\n';
}

std::string Script(const PulloffLawOptions& o, const std::string& data, const std::string& limit,
                   const std::string& output, double capacity_n, double shear_n, double y_max) {
  char title[320];
  std::snprintf(title, sizeof(title),
                "%g x %g mm pad, %d x %d bonds, lever %g mm. von Mises: sigma_T %g kPa, mu %g. "
                "Frictional: alpha* %g deg, tau_max %g kPa, friction %g",
                o.pad.width_m * 1e3, o.pad.length_m * 1e3, o.pad.grid_x, o.pad.grid_y,
                o.arm_m * 1e3, o.pad.sigma_t_pa * 1e-3, o.pad.mu, o.law.critical_angle_deg,
                o.law.shear_limit_pa * 1e-3, o.law.friction_mu);
  const double span = 1.6 * std::max(capacity_n, shear_n);
  std::ostringstream s;
  s << "set terminal pngcairo size 1400,620 font \",11\" noenhanced\n"
    << "set output " << output << "\n"
    << "set datafile separator \",\"\n"
    << "set multiplot layout 1,2 title " << common::GnuplotQuote(title) << "\n"
    << "set grid\nset key bottom left Left reverse\n"
    << "set title \"limit curve: the pad holds inside\"\n"
    << "set xlabel \"F_t, shear along the gripping direction (N)\"\n"
    << "set ylabel \"F_n, normal pull (N), + off the surface\"\n"
    << "set xrange [" << -span << ":" << span << "]\nset yrange [" << -0.6 * span << ":"
    << 1.1 * capacity_n << "]\n"
    << "plot " << limit << " index 0 using 1:2 with lines lw 2 lc rgb \"#1e8449\" "
    << "title \"frictional, closed form\", \\\n     " << limit
    << " index 2 using 1:2 with points pt 7 ps 0.7 lc rgb \"#1e8449\" "
    << "title \"frictional, bond grid\", \\\n     " << limit
    << " index 1 using 1:2 with lines lw 2 dt 2 lc rgb \"#c0392b\" "
    << "title \"von Mises, closed form\", \\\n     " << limit
    << " index 3 using 1:2 with points pt 5 ps 0.6 lc rgb \"#c0392b\" "
    << "title \"von Mises, bond grid\"\n"
    << "set title \"pull-off force against the pull angle\"\n"
    << "set key top left Left reverse\n"
    << "set xlabel \"pull angle from the surface normal (deg): 0 pulls off, 90 shears, 180 "
       "pushes\"\n"
    << "set ylabel \"pull-off force (N)\"\n"
    << "set xrange [" << o.from_deg << ":" << o.to_deg << "]\nset yrange [0:" << y_max << "]\n"
    << "set xtics 15\n"
    << "plot " << data
    << " using 1:2 skip 1 with points pt 7 ps 0.8 lc rgb \"#1e8449\" "
       "title \"frictional, along the grip (bond grid)\", \\\n     "
    << limit
    << " index 4 using 1:2 with lines lw 1.5 lc rgb \"#1e8449\" title \"frictional, closed "
       "form\", \\\n     "
    << data
    << " using 1:4 skip 1 with points pt 6 ps 0.8 lc rgb \"#7d3c98\" "
       "title \"frictional, against the grip (bond grid)\", \\\n     "
    << data
    << " using 1:6 skip 1 with points pt 5 ps 0.6 lc rgb \"#c0392b\" title \"von Mises (bond "
       "grid)\", \\\n     "
    << limit
    << " index 4 using 1:3 with lines dt 2 lw 1.5 lc rgb \"#c0392b\" title \"von Mises, closed "
       "form\"\n"
    << "unset multiplot\n";
  return s.str();
}

}  // namespace

namespace {

// The pad's forces and limits, each law's computed once.
struct LawSetup {
  double area = 0.0;      // pad area, m²
  double capacity = 0.0;  // sigma_T A, N
  double shear = 0.0;     // tau_max A, N
  double grip = 0.0;      // the grip direction's azimuth, rad
};

// One row per angle from o.from_deg to o.to_deg: both laws along and against the grip on
// the bond grid, and their closed forms for a central pull.
std::vector<LawRow> LawRows(const PulloffLawOptions& o, const adhesion::FrictionalLaw& law,
                            const LawSetup& u) {
  adhesion::PulloffOptions qs;
  qs.max_force_factor = o.max_force_factor;
  std::vector<LawRow> rows;
  for (int k = 0;; ++k) {
    const double a = o.from_deg + k * o.step_deg;
    if (a > o.to_deg + 1e-3 * o.step_deg) break;
    LawRow r;
    r.angle_deg = std::min(a, o.to_deg);
    const double theta = r.angle_deg * kDeg;
    const adhesion::PullSetup along{.angle_rad = theta, .azimuth_rad = u.grip, .arm_m = o.arm_m};
    adhesion::PullSetup against = along;
    against.azimuth_rad += M_PI;
    r.frictional_n = adhesion::FrictionalPullOff(o.pad, o.law, along, qs).force_n;
    r.reversed_n = adhesion::FrictionalPullOff(o.pad, o.law, against, qs).force_n;
    r.von_mises_n = adhesion::PullOff(o.pad, along, qs).force_n;
    if (o.arm_m == 0.0) {
      r.frictional_closed_n = law.PulloffClosedForm(u.area, theta, along.azimuth_rad);
      r.reversed_closed_n = law.PulloffClosedForm(u.area, theta, against.azimuth_rad);
      r.von_mises_closed_n = adhesion::VonMisesPulloffClosedForm(u.capacity, theta, o.pad.mu);
    }
    rows.push_back(r);
  }
  return rows;
}

std::string LawCsv(const std::vector<LawRow>& rows, const LawSetup& u) {
  std::string csv =
      "angle_deg,frictional_n,frictional_closed_n,frictional_reversed_n,"
      "frictional_reversed_closed_n,von_mises_n,von_mises_closed_n,capacity_n,shear_limit_n\n";
  for (const LawRow& r : rows) {
    csv += Num(r.angle_deg) + ',' + Num(r.frictional_n) + ',' + Num(r.frictional_closed_n) + ',' +
           Num(r.reversed_n) + ',' + Num(r.reversed_closed_n) + ',' + Num(r.von_mises_n) + ',' +
           Num(r.von_mises_closed_n) + ',' + Num(u.capacity) + ',' + Num(u.shear) + '\n';
  }
  return csv;
}

// limit.csv: five blocks (gnuplot index 0..4), the limit curves and the closed forms.
std::string LimitCsv(const PulloffLawOptions& o, const adhesion::FrictionalLaw& law,
                     const std::vector<LawRow>& rows, const LawSetup& u) {
  const double clip = 3.0 * std::max(u.capacity, u.shear);
  std::ostringstream limit;
  limit << "# index 0: frictional limit boundary, closed form (ft_n, fn_n)\n";
  for (const auto& v :
       adhesion::FrictionalLimitBoundary(law, u.area, 2.0 * std::max(u.capacity, u.shear))) {
    limit << Num(v.ft_n) << ',' << Num(v.fn_n) << '\n';
  }
  limit << "\n\n# index 1: von Mises limit curve, closed form (central pull, fine grid)\n";
  for (int k = 1800; k >= 0; --k) {  // against d, from pushing to pulling off
    Point(&limit, adhesion::VonMisesPulloffClosedForm(u.capacity, k * 0.1 * kDeg, o.pad.mu),
          k * 0.1 * kDeg, -1.0, clip);
  }
  for (int k = 0; k <= 1800; ++k) {
    Point(&limit, adhesion::VonMisesPulloffClosedForm(u.capacity, k * 0.1 * kDeg, o.pad.mu),
          k * 0.1 * kDeg, 1.0, clip);
  }
  limit << "\n\n# index 2: frictional pull-off vectors on the bond grid\n";
  for (const LawRow& r : rows) {
    Point(&limit, r.frictional_n, r.angle_deg * kDeg, 1.0, clip);
    Point(&limit, r.reversed_n, r.angle_deg * kDeg, -1.0, clip);
  }
  limit << "\n\n# index 3: von Mises pull-off vectors on the bond grid\n";
  for (const LawRow& r : rows) {
    Point(&limit, r.von_mises_n, r.angle_deg * kDeg, 1.0, clip);
    Point(&limit, r.von_mises_n, r.angle_deg * kDeg, -1.0, clip);
  }

  limit << "\n\n# index 4: closed forms against angle (angle_deg, frictional_n, "
           "von_mises_n), central pull along the grip\n";
  if (o.arm_m == 0.0) {
    for (int k = 0;; ++k) {
      const double a = o.from_deg + 0.25 * k;
      if (a > o.to_deg) break;
      const double f = law.PulloffClosedForm(u.area, a * kDeg, u.grip);
      const double v = adhesion::VonMisesPulloffClosedForm(u.capacity, a * kDeg, o.pad.mu);
      limit << Num(a) << ',' << (f <= clip ? Num(f) : "") << ',' << (v <= clip ? Num(v) : "")
            << '\n';
    }
  }
  return limit.str();
}

void PrintLawTable(const PulloffLawOptions& o, const std::vector<LawRow>& rows,
                   const LawSetup& u, const std::string& error) {
  std::printf(
      "climbsim pulloff --law frictional: %zu angles; sigma_T*A = %.4g N, tau_max*A = %.4g N, "
      "alpha* = %g deg\n",
      rows.size(), u.capacity, u.shear, o.law.critical_angle_deg);
  std::printf("%9s %12s %12s %8s %12s %12s %12s %8s\n", "angle_deg", "frictional_n",
              "closed_n", "diff_%", "reversed_n", "von_mises_n", "vm_closed_n", "diff_%");
  for (const LawRow& r : rows) {
    const auto diff = [](double a, double b) -> std::string {
      if (a == 0.0 && b == 0.0) return "0";
      if (std::isinf(a) && std::isinf(b)) return "0";
      const double d = 100.0 * (a / b - 1.0);
      return std::isfinite(d) ? Num(d) : "-";
    };
    std::printf("%9g %12s %12s %8s %12s %12s %12s %8s\n", r.angle_deg,
                Num(r.frictional_n).c_str(), Num(r.frictional_closed_n).c_str(),
                diff(r.frictional_n, r.frictional_closed_n).c_str(), Num(r.reversed_n).c_str(),
                Num(r.von_mises_n).c_str(), Num(r.von_mises_closed_n).c_str(),
                diff(r.von_mises_n, r.von_mises_closed_n).c_str());
  }
  std::printf("  outputs %s/{pulloff.csv,limit.csv,pulloff.gp%s}\n", o.out_dir.c_str(),
              error.empty() ? ",pulloff.png" : "");
}

}  // namespace

bool RunPulloffLaws(const PulloffLawOptions& o) {
  adhesion::ValidatePadParams(o.pad);
  const adhesion::FrictionalLaw law(o.law);
  sim::RunFolder folder(
      o.out_dir, {.made_by = "pulloff", .force = o.force, .keep_other_files = o.keep_other_files});
  const std::string dir = folder.path();

  LawSetup u;
  u.area = o.pad.width_m * o.pad.length_m;
  u.capacity = o.pad.sigma_t_pa * u.area;
  u.shear = o.law.shear_limit_pa * u.area;
  u.grip = std::atan2(law.grip_y(), law.grip_x());
  const std::vector<LawRow> rows = LawRows(o, law, u);
  common::WriteFileAtomic(dir + "/pulloff.csv", LawCsv(rows, u));
  common::WriteFileAtomic(dir + "/limit.csv", LimitCsv(o, law, rows, u));
  double y_max = 0.0;
  for (const LawRow& r : rows) {
    for (double f : {r.frictional_n, r.reversed_n, r.von_mises_n}) {
      if (std::isfinite(f)) y_max = std::max(y_max, f);
    }
  }
  y_max = std::min(3.0 * std::max(u.capacity, u.shear), 1.15 * y_max);
  // pulloff.gp names no folder: a user runs it where it lies, as gnuplot runs it here.
  const std::string data = common::GnuplotQuote("pulloff.csv");
  const std::string limits = common::GnuplotQuote("limit.csv");
  common::WriteFileAtomic(dir + "/pulloff.gp",
                          "# cd into this folder and run: gnuplot pulloff.gp\n" +
                              Script(o, data, limits, common::GnuplotQuote("pulloff.png"),
                                     u.capacity, u.shear, y_max));
  const std::string error = common::RunGnuplot(
      dir, Script(o, data, limits, "OUTPUT(0)", u.capacity, u.shear, y_max), {"pulloff.png"});
  folder.Commit();
  if (!o.quiet) PrintLawTable(o, rows, u, error);
  if (!error.empty()) std::fprintf(stderr, "climbsim pulloff: no plot: %s\n", error.c_str());
  return error.empty();
}

}  // namespace climbsim::optimise
