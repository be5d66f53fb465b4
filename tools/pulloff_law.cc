#include "tools/pulloff_law.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

#include "common/common.h"
#include "sim/sim.h"
#include "tools/commands.h"

namespace climbsim::tools {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct LawRow {
  double angle_deg = 0.0;
  double frictional_n = 0.0, frictional_closed_n = kNaN;
  double reversed_n = 0.0, reversed_closed_n = kNaN;
  double von_mises_n = 0.0, von_mises_closed_n = kNaN;
};

std::string Num(double v) {
  if (std::isnan(v)) return "";
  if (std::isinf(v)) return "inf";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

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

void RunPulloffLaws(const PulloffLawOptions& o) {
  adhesion::ValidatePadParams(o.pad);
  const adhesion::FrictionalLaw law(o.law);
  sim::RunFolder folder(o.out_dir, {.made_by = "pulloff", .force = o.force});
  const std::string dir = folder.path();

  const double area = o.pad.width_m * o.pad.length_m;
  const double capacity = o.pad.sigma_t_pa * area;
  const double shear = o.law.shear_limit_pa * area;
  const double grip = std::atan2(law.grip_y(), law.grip_x());
  adhesion::PulloffOptions qs;
  qs.max_force_factor = o.max_force_factor;
  std::vector<LawRow> rows;
  for (int k = 0;; ++k) {
    const double a = o.from_deg + k * o.step_deg;
    if (a > o.to_deg + 1e-3 * o.step_deg) break;
    LawRow r;
    r.angle_deg = std::min(a, o.to_deg);
    const double theta = r.angle_deg * kDeg;
    const adhesion::PullSetup along{.angle_rad = theta, .azimuth_rad = grip, .arm_m = o.arm_m};
    adhesion::PullSetup against = along;
    against.azimuth_rad += M_PI;
    r.frictional_n = adhesion::FrictionalPullOff(o.pad, o.law, along, qs).force_n;
    r.reversed_n = adhesion::FrictionalPullOff(o.pad, o.law, against, qs).force_n;
    r.von_mises_n = adhesion::PullOff(o.pad, along, qs).force_n;
    if (o.arm_m == 0.0) {
      r.frictional_closed_n = law.PulloffClosedForm(area, theta, along.azimuth_rad);
      r.reversed_closed_n = law.PulloffClosedForm(area, theta, against.azimuth_rad);
      r.von_mises_closed_n = adhesion::VonMisesPulloffClosedForm(capacity, theta, o.pad.mu);
    }
    rows.push_back(r);
  }

  // pulloff.csv
  std::string csv =
      "angle_deg,frictional_n,frictional_closed_n,frictional_reversed_n,"
      "frictional_reversed_closed_n,von_mises_n,von_mises_closed_n,capacity_n,shear_limit_n\n";
  for (const LawRow& r : rows) {
    csv += Num(r.angle_deg) + ',' + Num(r.frictional_n) + ',' + Num(r.frictional_closed_n) + ',' +
           Num(r.reversed_n) + ',' + Num(r.reversed_closed_n) + ',' + Num(r.von_mises_n) + ',' +
           Num(r.von_mises_closed_n) + ',' + Num(capacity) + ',' + Num(shear) + '\n';
  }
  // limit.csv: four blocks (gnuplot index 0..3).
  const double clip = 3.0 * std::max(capacity, shear);
  std::ostringstream limit;
  limit << "# index 0: frictional limit boundary, closed form (ft_n, fn_n)\n";
  for (const auto& v : adhesion::FrictionalLimitBoundary(law, area, 2.0 * std::max(capacity, shear))) {
    limit << Num(v.ft_n) << ',' << Num(v.fn_n) << '\n';
  }
  limit << "\n\n# index 1: von Mises limit curve, closed form (central pull, fine grid)\n";
  for (int k = 1800; k >= 0; --k) {  // against d, from pushing to pulling off
    Point(&limit, adhesion::VonMisesPulloffClosedForm(capacity, k * 0.1 * kDeg, o.pad.mu),
          k * 0.1 * kDeg, -1.0, clip);
  }
  for (int k = 0; k <= 1800; ++k) {
    Point(&limit, adhesion::VonMisesPulloffClosedForm(capacity, k * 0.1 * kDeg, o.pad.mu),
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
      const double f = law.PulloffClosedForm(area, a * kDeg, grip);
      const double v = adhesion::VonMisesPulloffClosedForm(capacity, a * kDeg, o.pad.mu);
      limit << Num(a) << ',' << (f <= clip ? Num(f) : "") << ',' << (v <= clip ? Num(v) : "")
            << '\n';
    }
  }
  const std::string csv_path = dir + "/pulloff.csv";
  const std::string limit_path = dir + "/limit.csv";
  const std::string png_path = dir + "/pulloff.png";
  common::WriteFileAtomic(csv_path, csv);
  common::WriteFileAtomic(limit_path, limit.str());
  double y_max = 0.0;
  for (const LawRow& r : rows) {
    for (double f : {r.frictional_n, r.reversed_n, r.von_mises_n}) {
      if (std::isfinite(f)) y_max = std::max(y_max, f);
    }
  }
  y_max = std::min(3.0 * std::max(capacity, shear), 1.15 * y_max);
  common::WriteFileAtomic(dir + "/pulloff.gp",
                       "# cd into this folder and run: gnuplot pulloff.gp\n" +
                           Script(o, "\"pulloff.csv\"", "\"limit.csv\"", "\"pulloff.png\"",
                                  capacity, shear, y_max));
  const std::string error =
      common::RunGnuplot(Script(o, common::GnuplotQuote(csv_path), common::GnuplotQuote(limit_path),
                             "OUTPUT(0)", capacity, shear, y_max),
                      {png_path});
  folder.Commit();

  if (!o.quiet) {
    std::printf(
        "climbsim pulloff --law frictional: %zu angles; sigma_T*A = %.4g N, tau_max*A = %.4g N, "
        "alpha* = %g deg\n",
        rows.size(), capacity, shear, o.law.critical_angle_deg);
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
  if (!error.empty()) {
    std::fprintf(stderr, "climbsim pulloff: no plot: %s\n", error.c_str());
    ExitCode() = 1;
  }
}

}  // namespace climbsim::tools
