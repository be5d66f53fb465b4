// climbsim fit-adhesion's run folder: the fitted parameters, the residuals, the curves of the
// three laws, the plot, fitted.yaml and the verdict (fit_adhesion.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/common.h"
#include "common/run_folder.h"
#include "experiments/fit_adhesion.h"

namespace climbsim::optimise {
namespace {

const char* const kLaws[] = {"von_mises", "frictional", "tabulated"};

std::string Num(double v) {
  if (std::isnan(v)) return "";
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

// A name for a comment: printable ASCII only (a file name never breaks the YAML).
std::string Printable(const std::string& s) {
  std::string out;
  for (char c : s) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  return out;
}

std::string ParametersCsv(const AdhesionFit& fit) {
  std::string csv = "key,unit,angle_from_normal_deg,azimuth_deg,value,uncertainty,low95,high95\n";
  size_t node = 0;
  for (const FittedParameter& p : fit.parameters) {
    std::string angle, azimuth;
    if (p.key == "tabulated.pulloff_n") {
      angle = Num(fit.tabulated.angle_from_normal_deg[node]);
      if (!fit.tabulated.azimuth_deg.empty()) azimuth = Num(fit.tabulated.azimuth_deg[node]);
      ++node;
    }
    csv += p.key + ',' + p.unit + ',' + angle + ',' + azimuth + ',' + Num(p.value) + ',' +
           Num(p.uncertainty) + ',' + Num(p.low95) + ',' + Num(p.high95) + '\n';
  }
  return csv;
}

// One row per measurement: the chosen law's prediction and residual, then every law's.
std::string ResidualsCsv(const PulloffData& d, const AdhesionFit& fit,
                         const std::vector<AdhesionFit>& all) {
  std::string csv =
      "line,angle_from_normal_deg,azimuth_deg,pad_width_m,pad_length_m,lever_arm_m,preload_n,"
      "repeat,force_n,predicted_n,residual_n,von_mises_n,frictional_n,tabulated_n\n";
  for (size_t k = 0; k < d.rows.size(); ++k) {
    const PulloffMeasurement& r = d.rows[k];
    csv += std::to_string(r.line) + ',' + Num(r.angle_from_normal_deg) + ',' +
           Num(r.azimuth_deg) + ',' + Num(r.width_m) + ',' + Num(r.length_m) + ',' +
           Num(r.arm_m) + ',' + Num(r.preload_n) + ',' + std::to_string(r.repeat) + ',' +
           Num(r.force_n) + ',' + Num(fit.predicted_n[k]) + ',' +
           Num(r.force_n - fit.predicted_n[k]);
    for (const AdhesionFit& f : all) csv += ',' + (f.law.empty() ? "" : Num(f.predicted_n[k]));
    csv += '\n';
  }
  return csv;
}

// The three laws' curves against angle, at the first row's pad and lever, one block per
// azimuth of the data (blank lines between: gnuplot draws each block as its own line).
std::string CurvesCsv(const PulloffData& d, const std::vector<AdhesionFit>& all, int grid,
                      double max_angle_deg) {
  std::vector<double> azimuths;
  for (const auto& r : d.rows) {
    if (std::find(azimuths.begin(), azimuths.end(), r.azimuth_deg) == azimuths.end())
      azimuths.push_back(r.azimuth_deg);
  }
  std::string csv = "angle_from_normal_deg,azimuth_deg,von_mises_n,frictional_n,tabulated_n\n";
  for (size_t b = 0; b < azimuths.size() && b < 6; ++b) {
    if (b) csv += "\n";
    for (double a = 0.0; a <= max_angle_deg + 1e-9; a += 1.0) {
      PulloffMeasurement row = d.rows[0];
      row.angle_from_normal_deg = a;
      row.azimuth_deg = azimuths[b];
      csv += Num(a) + ',' + Num(azimuths[b]);
      for (const AdhesionFit& f : all) {
        csv += ',' + (f.law.empty() ? "" : Num(PredictPulloff(f, row, grid)));
      }
      csv += '\n';
    }
  }
  return csv;
}

// The plot: no user text reaches it (file names are fixed, titles are ours).
std::string Script(const std::string& law, const std::string& output, double max_angle_deg,
                   const std::vector<AdhesionFit>& all) {
  std::ostringstream s;
  s << "set terminal pngcairo size 1000,640 font \",11\" noenhanced\n"
    << "set output " << output << "\n"
    << "set datafile separator \",\"\n"
    << "set title " << common::GnuplotQuote("Measured pull-off against the fitted laws (" + law +
                                            " chosen), first row's pad and lever")
    << "\n"
    << "set xlabel \"pull angle from the pad normal (deg): 0 pulls straight off, 90 shears\"\n"
    << "set ylabel \"pull-off force (N)\"\n"
    << "set xrange [0:" << max_angle_deg << "]\nset yrange [0:*]\nset grid\n"
    << "set key top left\n"
    << "plot \"residuals.csv\" using 2:9 skip 1 with points pt 7 ps 1.2 lc rgb \"#000000\" "
       "title \"measured\"";
  const char* colours[] = {"#c0392b", "#1e8449", "#2471a3"};
  for (int i = 0; i < 3; ++i) {
    if (all[i].law.empty()) continue;
    const bool chosen = all[i].law == law;
    s << ", \\\n     \"curves.csv\" using 1:" << 3 + i << " skip 1 with lines lw "
      << (chosen ? 3 : 1.5) << " dt " << (chosen ? 1 : 2) << " lc rgb \"" << colours[i]
      << "\" title \"" << kLaws[i] << (chosen ? " (fitted)" : " (best fit)") << "\"";
  }
  s << "\n";
  return s.str();
}

std::string VerdictText(const AdhesionFit& fit, const std::vector<AdhesionFit>& all) {
  std::string text = fit.verdict + "\n";
  for (const AdhesionFit& f : all) {
    if (!f.law.empty() && f.law != fit.law) text += "  other law, " + f.verdict + "\n";
  }
  return text;
}

void PrintFit(const AdhesionFit& fit, const PulloffData& d, double wall_s) {
  std::printf("climbsim fit-adhesion: %zu measurements, law %s, %d evaluations in %.2f s\n",
              d.rows.size(), fit.law.c_str(), fit.evaluations, wall_s);
  size_t node = 0;
  for (const FittedParameter& p : fit.parameters) {
    std::string where;
    if (p.key == "tabulated.pulloff_n") {
      where = " at " + Num(fit.tabulated.angle_from_normal_deg[node]) + " deg";
      ++node;
    }
    std::printf("  %-32s %12s +- %-10s %s\n", (p.key + where).c_str(), Num(p.value).c_str(),
                std::isnan(p.uncertainty) ? "-" : Num(p.uncertainty).c_str(), p.unit.c_str());
  }
}

}  // namespace

std::string FittedYaml(const AdhesionFit& fit, const PulloffData& data) {
  std::ostringstream y;
  y << "# climbsim fit-adhesion from " << Printable(data.file) << ", law " << fit.law
    << " through the bond grid\n# " << fit.verdict << "\nadhesion:\n  law: " << fit.law << "\n";
  if (fit.law == "von_mises") {
    y << "  sigma_t_pa: " << Num(fit.von_mises.sigma_t_pa) << "\n  mu: " << Num(fit.von_mises.mu)
      << "\n";
  } else if (fit.law == "frictional") {
    y << "  frictional:\n    shear_limit_pa: " << Num(fit.frictional.shear_limit_pa)
      << "\n    critical_angle_deg: " << Num(fit.frictional.critical_angle_deg)
      << "\n    friction_mu: " << Num(fit.frictional.friction_mu)
      << "\n    # grip_x, grip_y: the scenario's; the data's azimuth "
      << Num(std::atan2(fit.frictional.grip_y, fit.frictional.grip_x) * 180.0 / M_PI)
      << " deg was taken as the gripping direction\n";
  } else {
    const adhesion::TabulatedParams& t = fit.tabulated;
    const auto list = [](const std::vector<double>& v) {
      std::string s = "[";
      for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Num(v[i]);
      return s + "]";
    };
    y << "  tabulated:\n    width_m: " << Num(t.width_m) << "\n    length_m: " << Num(t.length_m)
      << "\n    angle_from_normal_deg: " << list(t.angle_from_normal_deg) << "\n";
    if (!t.azimuth_deg.empty()) y << "    azimuth_deg: " << list(t.azimuth_deg) << "\n";
    y << "    pulloff_n: " << list(t.pulloff_n) << "\n";
  }
  return y.str();
}

bool RunFitAdhesion(const FitAdhesionRunOptions& o) {
  const PulloffData data = ReadPulloffCsv(o.data_file, o.width_m, o.length_m);
  CheckFitData(data, o.fit.law);  // before the folder: bad input changes nothing
  sim::RunFolder folder(o.out_dir, {.made_by = "fit-adhesion",
                                    .force = o.force,
                                    .keep_other_files = o.keep_other_files,
                                    .inputs = {o.data_file}});
  const auto started = std::chrono::steady_clock::now();
  std::vector<AdhesionFit> all(3);
  AdhesionFit fit;
  for (int i = 0; i < 3; ++i) {
    FitAdhesionOptions options = o.fit;
    options.law = kLaws[i];
    if (options.law != o.fit.law) options.progress = nullptr;
    try {
      all[i] = FitAdhesion(data, options);
    } catch (const InputError&) {
      if (options.law == o.fit.law) throw;  // tabulated over 90 deg: the others still plot
    }
    if (options.law == o.fit.law) fit = all[i];
    if (o.fit.progress) o.fit.progress("fit-adhesion: " + options.law + " fitted");
  }
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  double max_angle = 90.0;
  for (const auto& r : data.rows) max_angle = std::max(max_angle, r.angle_from_normal_deg);
  const std::string dir = folder.path();
  common::WriteFileAtomic(dir + "/parameters.csv", ParametersCsv(fit));
  common::WriteFileAtomic(dir + "/residuals.csv", ResidualsCsv(data, fit, all));
  common::WriteFileAtomic(dir + "/curves.csv", CurvesCsv(data, all, o.fit.grid, max_angle));
  common::WriteFileAtomic(dir + "/fitted.yaml", FittedYaml(fit, data));
  common::WriteFileAtomic(dir + "/verdict.txt", VerdictText(fit, all));
  common::WriteFileAtomic(dir + "/fit.gp", "# cd into this folder and run: gnuplot fit.gp\n" +
                                               Script(fit.law, common::GnuplotQuote("fit.png"),
                                                      max_angle, all));
  const std::string error =
      common::RunGnuplot(dir, Script(fit.law, "OUTPUT(0)", max_angle, all), {"fit.png"});
  folder.Commit();
  if (!o.quiet) {
    PrintFit(fit, data, wall_s);
    std::printf("%s  outputs %s/{parameters.csv,residuals.csv,curves.csv,fitted.yaml,verdict.txt,"
                "fit.gp%s}\n",
                VerdictText(fit, all).c_str(), o.out_dir.c_str(), error.empty() ? ",fit.png" : "");
  }
  if (!error.empty()) std::fprintf(stderr, "climbsim fit-adhesion: no plot: %s\n", error.c_str());
  return error.empty();
}

}  // namespace climbsim::optimise
