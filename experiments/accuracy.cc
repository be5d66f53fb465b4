#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <thread>

#include "adhesion/adhesion.h"
#include "experiments/experiments.h"
#include "common/common.h"

namespace climbsim::optimise {
namespace {

using Clock = std::chrono::steady_clock;

struct Setting {
  std::string knob, label;
  std::vector<std::pair<std::string, std::string>> keys;  // dotted key → YAML value text
};

// The settings: the reference (finest of every knob at once), then each knob swept with
// the others as the scenario has them.
std::vector<Setting> Settings(const sim::Scenario& s) {
  std::vector<Setting> out;
  std::vector<std::pair<std::string, std::string>> finest = {
      {"physics.timestep_s", "0.00025"}, {"physics.integrator", "rk4"},
      {"physics.solver_iterations", "300"}, {"physics.solver_tolerance", "1e-12"}};
  if (s.adhesion) {
    finest.push_back({"adhesion.grid_x", "32"});
    finest.push_back({"adhesion.grid_y", "32"});
  }
  if (s.cpg) {
    finest.push_back({"cpg.stepper", "dopri5"});
    finest.push_back({"cpg.abs_tol", "1e-10"});
    finest.push_back({"cpg.rel_tol", "1e-10"});
  }
  out.push_back({"reference", "finest", finest});
  for (const char* dt : {"0.002", "0.001", "0.0005", "0.00025"}) {
    out.push_back({"time step", std::string(dt) + " s", {{"physics.timestep_s", dt}}});
  }
  for (const char* in : {"euler", "implicit", "rk4"}) {
    out.push_back({"integrator", in, {{"physics.integrator", in}}});
  }
  // The cone is a friction model, not a discretisation: the reference keeps the scene's.
  for (const char* c : {"elliptic", "pyramidal"}) {
    out.push_back({"friction cone", c, {{"physics.cone", c}}});
  }
  for (const char* it : {"5", "20", "100", "300"}) {
    out.push_back({"solver iterations", it, {{"physics.solver_iterations", it}}});
  }
  for (const char* tol : {"1e-4", "1e-6", "1e-8", "1e-12"}) {
    out.push_back({"solver tolerance", tol, {{"physics.solver_tolerance", tol}}});
  }
  if (s.adhesion) {
    for (const char* g : {"4", "8", "16", "32"}) {
      out.push_back({"bond grid", std::string(g) + "x" + g,
                     {{"adhesion.grid_x", g}, {"adhesion.grid_y", g}}});
    }
  }
  if (s.cpg) {
    out.push_back({"odeint stepper", "euler", {{"cpg.stepper", "euler"}}});
    out.push_back({"odeint stepper", "rk4", {{"cpg.stepper", "rk4"}}});
    out.push_back({"odeint stepper", "dopri5 1e-6",
                   {{"cpg.stepper", "dopri5"}, {"cpg.abs_tol", "1e-6"}, {"cpg.rel_tol", "1e-6"}}});
    out.push_back(
        {"odeint stepper",
         "dopri5 1e-10",
         {{"cpg.stepper", "dopri5"}, {"cpg.abs_tol", "1e-10"}, {"cpg.rel_tol", "1e-10"}}});
  }
  return out;
}

AccuracyRun Measure(const sim::Scenario& s, ModelCache* cache) {
  AccuracyRun r;
  const auto t0 = Clock::now();
  sim::Simulation run(s, cache->For(s));
  const sim::RunResult res = run.Run();
  r.stable = res.stable;
  r.fell = res.fell;
  r.distance_m = res.distance_m;
  const int pads = static_cast<int>(run.events().pad_names().size());
  r.detach_s.assign(pads, {});
  r.peak_load_n.assign(pads, 0.0);
  for (const sim::Event& e : run.events().rows()) {
    if (e.pad < 0) continue;
    if (std::string_view(e.kind) == "detach") r.detach_s[e.pad].push_back(e.time_s);
    const double f =
        std::sqrt(e.load[0] * e.load[0] + e.load[1] * e.load[1] + e.load[2] * e.load[2]);
    r.peak_load_n[e.pad] = std::max(r.peak_load_n[e.pad], f);
  }
  // Pull-off at 45° of a pad of this material on this time step and grid (adhesion only).
  if (s.adhesion) {
    adhesion::PulloffRigParams p;
    p.pad.sigma_t_pa = s.adhesion->sigma_t_pa;
    p.pad.mu = s.adhesion->mu;
    p.pad.grid_x = s.adhesion->grid_x;
    p.pad.grid_y = s.adhesion->grid_y;
    p.timestep_s = run.world().model()->opt.timestep;
    adhesion::PulloffRig rig(adhesion::AdhesionModel::kBonds, p);
    r.pulloff_n = rig.Run(M_PI / 4).force_n;
  }
  r.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  return r;
}

}  // namespace

AccuracyReport BenchAccuracy(const std::string& file, double duration_s, int threads) {
  const YAML::Node root = sim::LoadYamlFile(file);
  const sim::Scenario base = sim::ParseScenario(root, file);
  const std::vector<Setting> settings = Settings(base);
  std::vector<sim::Scenario> scenarios;
  for (const Setting& set : settings) {
    YAML::Node tree = YAML::Clone(root);
    SetDottedKeyText(tree, "duration_s", sim::ExactNumber(duration_s));
    for (const auto& [key, value] : set.keys) SetDottedKeyText(tree, key, value);
    scenarios.push_back(sim::ParseScenario(tree, file));
  }
  std::vector<AccuracyRun> runs(settings.size());
  // Slowest first (the reference), so two threads finish together.
  const int n = threads > 0 ? threads : static_cast<int>(std::thread::hardware_concurrency());
  ParallelRollouts(static_cast<int>(runs.size()), n,
                   [&](int t, ModelCache& cache) { runs[t] = Measure(scenarios[t], &cache); });

  AccuracyReport report;
  report.duration_s = duration_s;
  report.reference = runs[0];
  const AccuracyRun& ref = runs[0];
  for (size_t i = 1; i < runs.size(); ++i) {
    const AccuracyRun& r = runs[i];
    AccuracyRow row;
    row.knob = settings[i].knob;
    row.setting = settings[i].label;
    row.run = r;
    row.distance_error_m = std::abs(r.distance_m - ref.distance_m);
    // Detaches matched in order per pad; the unmatched are counted.
    double sum = 0.0;
    int matched = 0;
    for (size_t p = 0; p < r.detach_s.size() && p < ref.detach_s.size(); ++p) {
      const size_t k = std::min(r.detach_s[p].size(), ref.detach_s[p].size());
      for (size_t j = 0; j < k; ++j) sum += std::abs(r.detach_s[p][j] - ref.detach_s[p][j]);
      matched += static_cast<int>(k);
      row.detach_count_diff += static_cast<int>(
          std::max(r.detach_s[p].size(), ref.detach_s[p].size()) - k);
    }
    row.detach_time_error_s = matched > 0 ? sum / matched : 0.0;
    for (size_t p = 0; p < r.peak_load_n.size() && p < ref.peak_load_n.size(); ++p) {
      if (ref.peak_load_n[p] > 0) {
        row.peak_load_error =
            std::max(row.peak_load_error,
                     std::abs(r.peak_load_n[p] - ref.peak_load_n[p]) / ref.peak_load_n[p]);
      }
    }
    if (ref.pulloff_n > 0 && std::isfinite(ref.pulloff_n)) {
      row.pulloff_error = std::abs(r.pulloff_n - ref.pulloff_n) / ref.pulloff_n;
    }
    report.rows.push_back(row);
  }
  return report;
}

std::string WriteAccuracy(const std::string& dir, const AccuracyReport& report) {
  std::filesystem::create_directories(dir);
  std::string csv =
      "knob,setting,wall_time_s,distance_m,distance_error_m,detach_time_error_s,"
      "detach_count_diff,peak_load_error,pulloff_n,pulloff_error,fell,stable\n";
  auto line = [](const std::string& knob, const std::string& setting, const AccuracyRun& r,
                 double de, double dt, int dc, double pe, double po) {
    return knob + "," + setting + "," + sim::ExactNumber(r.wall_s) + "," +
           sim::ExactNumber(r.distance_m) + "," + sim::ExactNumber(de) + "," +
           sim::ExactNumber(dt) + "," + std::to_string(dc) + "," + sim::ExactNumber(pe) + "," +
           sim::ExactNumber(r.pulloff_n) + "," + sim::ExactNumber(po) + "," +
           (r.fell ? "1" : "0") + "," + (r.stable ? "1" : "0") + "\n";
  };
  csv += line("reference", "finest", report.reference, 0, 0, 0, 0, 0);
  for (const AccuracyRow& r : report.rows) {
    csv += line(r.knob, r.setting, r.run, r.distance_error_m, r.detach_time_error_s,
                r.detach_count_diff, r.peak_load_error, r.pulloff_error);
  }
  common::WriteFileAtomic(dir + "/accuracy.csv", csv);

  // One data block per knob (blank-line separated) so gnuplot draws one curve each.
  std::string data;
  std::vector<std::string> knobs;
  for (const AccuracyRow& r : report.rows) {
    if (knobs.empty() || knobs.back() != r.knob) {
      if (!knobs.empty()) data += "\n\n";
      knobs.push_back(r.knob);
    }
    // Zero errors cannot sit on a log axis: shown at 1e-7.
    data += sim::ExactNumber(r.run.wall_s) + " " +
            sim::ExactNumber(std::max(r.distance_error_m, 1e-7)) + " " +
            sim::ExactNumber(std::max(r.detach_time_error_s, 1e-7)) + " " +
            sim::ExactNumber(std::max(r.pulloff_error, 1e-7)) + "\n";
  }
  common::WriteFileAtomic(dir + "/accuracy.dat", data);
  std::string plot1, plot2, plot3;
  for (size_t k = 0; k < knobs.size(); ++k) {
    const std::string idx = std::to_string(k);
    const std::string sep = k ? ", " : "";
    const std::string title = " with linespoints lw 2 title " + common::GnuplotQuote(knobs[k]);
    plot1 += sep + "data index " + idx + " using 1:2" + title;
    plot2 += sep + "data index " + idx + " using 1:3" + title;
    plot3 += sep + "data index " + idx + " using 1:4" + title;
  }
  const std::string script =
      "set terminal pngcairo size 1400,480 noenhanced\nset output OUTPUT(0)\n"
      "set logscale xy\nset grid\nset key bottom left font ',8'\n"
      "data = 'accuracy.dat'\n"  // gnuplot runs in `dir`
      "set multiplot layout 1,3 title 'climbsim bench accuracy: error against wall time, one "
      "curve per knob (errors against the finest setting; 1e-7 = exact)'\n"
      "set xlabel 'wall time of the run [s]'\n"
      "set ylabel 'climbed distance error [m]'\nplot " + plot1 + "\n"
      "set ylabel 'detach time error [s]'\nplot " + plot2 + "\n"
      "set ylabel 'pull-off error at 45 deg [relative]'\nplot " + plot3 + "\n"
      "unset multiplot\n";
  return common::RunGnuplot(dir, script, {"accuracy.png"});
}

}  // namespace climbsim::optimise
