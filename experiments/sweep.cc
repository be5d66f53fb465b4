#include <algorithm>
#include <filesystem>
#include <cmath>
#include <stdexcept>

#include "optimise/comm.h"
#include "optimise/disturbance.h"
#include "optimise/text.h"
#include "experiments/experiments.h"
#include "common/common.h"

namespace climbsim::optimise {
namespace {

nlohmann::json ToJson(const SweepRun& run) {
  const sim::RunResult& r = run.result;
  return {r.stable, r.failure, r.steps, r.sim_time_s, r.wall_time_s, r.fell,
          r.fall_time_s, r.distance_m, r.heading_deg, r.actuator_work_j, run.summary};
}

SweepRun FromJson(const nlohmann::json& j) {
  SweepRun run;
  sim::RunResult& r = run.result;
  r.stable = j[0].get<bool>();
  r.failure = j[1].get<std::string>();
  r.steps = j[2].get<long>();
  r.sim_time_s = j[3].get<double>();
  r.wall_time_s = j[4].get<double>();
  r.fell = j[5].get<bool>();
  r.fall_time_s = j[6].get<double>();
  r.distance_m = j[7].get<double>();
  r.heading_deg = j[8].get<double>();
  r.actuator_work_j = j[9].get<double>();
  run.summary = j[10];
  run.stalled = run.summary.value("stalled", false);
  run.stall_time_s = run.stalled ? run.summary.value("stall_time_s", -1.0) : -1.0;
  return run;
}

// A point's scenario refused, as bad input at the swept key: the module's error names the
// key it refused, this names the file and the swept value that led there.
InputError PointError(const std::string& file, const SweepOptions& o, double v,
                      const InputError& e) {
  return InputError(file, 0, 0, o.key,
                    o.key + " = " + sim::ExactNumber(v) + " gives an invalid scenario: " + e.key() +
                        " " + e.message());
}

// The same for a refusal that is not an InputError (a module's std::invalid_argument).
InputError PointError(const std::string& file, const SweepOptions& o, double v,
                      const std::invalid_argument& e) {
  return InputError(file, 0, 0, o.key,
                    o.key + " = " + sim::ExactNumber(v) + " gives an invalid scenario: " +
                        e.what());
}

// Builds every point's simulation (and drops it) before any runs: a value the loader takes
// but the simulation refuses (cpg.control_period_s off the time step) is bad input before
// any work, the lowest point's, on every rank alike.
void CheckPointsBuild(const std::vector<std::string>& files, const std::vector<double>& values,
                      const std::vector<std::vector<sim::Scenario>>& scenarios,
                      const SweepOptions& o, int threads) {
  ParallelRollouts(static_cast<int>(values.size() * files.size()), threads,
                   [&](int t, ModelCache& cache) {
                     const size_t f = t % files.size(), i = t / files.size();
                     try {
                       sim::Simulation run(scenarios[f][i], cache.For(scenarios[f][i]));
                     } catch (const InputError& e) {
                       throw PointError(files[f], o, values[i], e);
                     } catch (const std::invalid_argument& e) {
                       throw PointError(files[f], o, values[i], e);
                     }
                   });
}

// sweep.png's script: per file the worst speed where no seed fell or stalled, and marks at 0
// where one fell (a cross) or stalled (a square).
std::string SweepScript(const SweepOptions& o, const std::vector<std::string>& names) {
  std::string plots;
  for (size_t f = 0; f < names.size(); ++f) {
    const int col = 3 + 7 * static_cast<int>(f);
    const std::string fell = "(column(" + std::to_string(col + 2) + ") > 0.5)";
    const std::string stalled = "(column(" + std::to_string(col + 4) + ") > 0.5)";
    const std::string lc = " lc " + std::to_string(f + 1);
    plots += std::string(f ? ", " : "") + "data using 1:(" + fell + " || " + stalled +
             " ? NaN : 100*column(" + std::to_string(col) + ")) with linespoints lw 2" + lc +
             " title " + common::GnuplotQuote(names[f]) + ", data using 1:(" + fell +
             " ? 0 : NaN) with points pt 2 ps 2" + lc + " title " +
             common::GnuplotQuote(names[f] + " fell") + ", data using 1:(" + stalled + " && !" +
             fell + " ? 0 : NaN) with points pt 4 ps 2" + lc + " title " +
             common::GnuplotQuote(names[f] + " stalled");
  }
  return "set terminal pngcairo size 900,560 noenhanced\nset output OUTPUT(0)\n"
         "set datafile separator ','\nset key top right\nset grid\n"
         "set title 'climbsim sweep: speed along the travel direction (worst seed)'\n"
         "set xlabel " + common::GnuplotQuote(o.key) + "\nset ylabel 'speed [cm/s]'\n"
         "data = 'sweep.csv'\n"  // gnuplot runs in `dir`
         "plot " + plots + "\n";
}

}  // namespace

int SweepPoint::fell() const {
  return static_cast<int>(std::count_if(seeds.begin(), seeds.end(),
                                        [](const SweepRun& r) { return r.result.fell; }));
}

int SweepPoint::stalled() const {
  return static_cast<int>(
      std::count_if(seeds.begin(), seeds.end(), [](const SweepRun& r) { return r.stalled; }));
}

double SweepPoint::first_fall_s() const {
  double t = -1.0;
  for (const SweepRun& r : seeds) {
    if (r.result.fell && (t < 0 || r.result.fall_time_s < t)) t = r.result.fall_time_s;
  }
  return t;
}

double SweepPoint::first_stall_s() const {
  double t = -1.0;
  for (const SweepRun& r : seeds) {
    if (r.stalled && (t < 0 || r.stall_time_s < t)) t = r.stall_time_s;
  }
  return t;
}

double SweepPoint::worst_speed_mps() const {
  if (seeds.empty() || fell() > 0 || stalled() > 0) return 0.0;
  double v = seeds[0].result.mean_speed_mps();
  for (const SweepRun& r : seeds) v = std::min(v, r.result.mean_speed_mps());
  return v;
}

double SweepPoint::mean_speed_mps() const {
  double sum = 0.0;
  for (const SweepRun& r : seeds) sum += r.result.mean_speed_mps();
  return seeds.empty() ? 0.0 : sum / static_cast<double>(seeds.size());
}

double SweepPoint::worst_distance_m() const {
  double d = seeds.empty() ? 0.0 : seeds[0].result.distance_m;
  for (const SweepRun& r : seeds) d = std::min(d, r.result.distance_m);
  return d;
}

void CheckSweepRange(const SweepOptions& o) {
  const auto bad = [](const char* flag, const std::string& m) {
    return InputError("climbsim sweep", 0, 0, flag, m);
  };
  if (!std::isfinite(o.from)) throw bad("--from", "must be a finite number");
  if (!std::isfinite(o.to)) throw bad("--to", "must be a finite number");
  if (!std::isfinite(o.step)) throw bad("--step", "must be a finite number");
  if (o.to < o.from) throw bad("--to", "must not be below --from");
  const double values = std::floor((o.to - o.from) / o.step + 1e-9) + 1;
  if (!(values <= kMaxSweepValues)) {
    throw bad("--step", "gives " + sim::ExactNumber(values) +
                            " values from --from to --to; at most " +
                            std::to_string(kMaxSweepValues) + " are allowed");
  }
  if (o.seeds < 1 || o.seeds > kMaxSweepSeeds) {
    throw bad("--seeds", "must be in [1, " + std::to_string(kMaxSweepSeeds) + "]");
  }
  if (!o.runs_dir.empty() && ProcessCount() > 1) {
    throw bad("--keep-runs", "keeps run folders in one process only (not under mpirun)");
  }
}

namespace {

// "4.21", or with several seeds "4.21 (2/3)": the first time, how many of the seeds.
std::string TimeCell(double t, int count, int seeds) {
  if (t < 0) return "-";
  char buf[48];
  if (seeds > 1) {
    std::snprintf(buf, sizeof(buf), "%.2f (%d/%d)", t, count, seeds);
  } else {
    std::snprintf(buf, sizeof(buf), "%.2f", t);
  }
  return buf;
}

}  // namespace

std::string SweepTable(const std::vector<std::string>& files, const SweepOptions& o,
                       const std::vector<SweepRow>& rows, const std::string& out_dir,
                       const std::string& warning) {
  const bool many = o.seeds > 1;
  std::string out;
  if (many) Appendf(&out, "%d seeds per point: worst and mean speed\n", o.seeds);
  Appendf(&out, "%12s", o.key.c_str());
  for (const auto& f : files) {
    Appendf(&out, many ? "  %55s" : "  %43s", std::filesystem::path(f).stem().string().c_str());
  }
  Appendf(&out, "\n%12s", "");
  for (size_t f = 0; f < files.size(); ++f) {
    Appendf(&out, "  %14s", many ? "worst [cm/s]" : "speed [cm/s]");
    if (many) Appendf(&out, " %11s", "mean [cm/s]");
    Appendf(&out, " %13s %14s", "fell at [s]", "stalled at [s]");
  }
  Appendf(&out, "\n");
  for (const auto& r : rows) {
    Appendf(&out, "%12g", r.value);
    for (const SweepPoint& p : r.points) {
      // A fall or a stall is not progress: no speed is shown for it.
      if (p.fell() > 0 || p.stalled() > 0) {
        Appendf(&out, "  %14s", "-");
      } else {
        Appendf(&out, "  %14.2f", 100 * p.worst_speed_mps());
      }
      if (many) Appendf(&out, " %11.2f", 100 * p.mean_speed_mps());
      Appendf(&out, " %13s %14s", TimeCell(p.first_fall_s(), p.fell(), o.seeds).c_str(),
              TimeCell(p.first_stall_s(), p.stalled(), o.seeds).c_str());
    }
    Appendf(&out, "\n");
  }
  Appendf(&out, "  outputs %s/{sweep.csv,sweep.png%s}%s%s\n", out_dir.c_str(),
          o.runs_dir.empty() ? "" : ",runs/", warning.empty() ? "" : "  (plot: ",
          warning.empty() ? "" : (warning + ")").c_str());
  return out;
}

std::vector<SweepRun> RunSweepPoints(const std::vector<sim::Scenario>& scenarios,
                                     const std::vector<std::string>& run_dirs, int threads) {
  std::vector<SweepRun> runs(scenarios.size());
  // Tasks in a fixed order, each writing its own slot: results do not depend on threads.
  // Under mpirun, task t runs on rank t mod N and the ranks exchange their results.
  const Comm& comm = Comm::World();
  const int all = static_cast<int>(scenarios.size());
  std::vector<int> mine;
  for (int t = comm.rank(); t < all; t += comm.size()) mine.push_back(t);
  ParallelRollouts(static_cast<int>(mine.size()), threads, [&](int m, ModelCache& cache) {
    const int t = mine[m];
    sim::Simulation run(scenarios[t], cache.For(scenarios[t]));
    SweepRun& out = runs[t];
    out.result = run.Run();
    out.summary = run.Summary();
    out.summary.erase("wall_time_s");  // the machine's, not the run's
    out.summary.erase("realtime_factor");
    out.stalled = out.summary.value("stalled", false);
    out.stall_time_s = out.stalled ? out.summary.value("stall_time_s", -1.0) : -1.0;
    if (!run_dirs.empty()) {
      std::filesystem::create_directories(run_dirs[t]);
      sim::WriteRunFiles(run_dirs[t], run);
    }
  });
  if (comm.size() > 1) {
    nlohmann::json local = nlohmann::json::array();
    for (int t : mine) local.push_back({t, ToJson(runs[t])});
    for (const std::string& part : comm.AllGather(local.dump())) {
      for (const auto& entry : nlohmann::json::parse(part)) {
        runs[entry[0].get<int>()] = FromJson(entry[1]);
      }
    }
  }
  return runs;
}

std::vector<SweepRow> Sweep(const std::vector<std::string>& files, const SweepOptions& o) {
  std::vector<double> values;
  const int n = static_cast<int>(std::floor((o.to - o.from) / o.step + 1e-9)) + 1;
  for (int i = 0; i < n; ++i) values.push_back(o.from + i * o.step);

  // Every scenario for every value, built (and so validated) before anything runs.
  std::vector<std::vector<sim::Scenario>> scenarios(files.size());
  for (size_t f = 0; f < files.size(); ++f) {
    const YAML::Node root = sim::LoadYamlFile(files[f]);
    sim::ParseScenario(root, files[f]);  // the file itself first, with its places
    for (double v : values) {
      YAML::Node tree = YAML::Clone(root);
      // SetDottedKey names the part of the key that does not fit; the file is added here.
      try {
        SetDottedKey(tree, o.key, v);
      } catch (const std::invalid_argument& e) {
        throw InputError(files[f], 0, 0, o.key, e.what());
      }
      try {
        scenarios[f].push_back(sim::ParseScenario(tree, files[f]));
      } catch (const InputError& e) {
        throw PointError(files[f], o, v, e);
      }
    }
  }
  const int threads = o.threads > 0 ? o.threads : DefaultThreads();
  CheckPointsBuild(files, values, scenarios, o, threads);

  // Task t: value t / (files·seeds), file (t / seeds) mod files, seed t mod seeds.
  const size_t nf = files.size(), ns = static_cast<size_t>(o.seeds);
  std::vector<sim::Scenario> tasks;
  std::vector<std::string> dirs;
  for (size_t i = 0; i < values.size(); ++i) {
    for (size_t f = 0; f < nf; ++f) {
      for (size_t k = 0; k < ns; ++k) {
        tasks.push_back(scenarios[f][i]);
        ApplyCaseSeed(&tasks.back(), static_cast<int>(k));
        if (o.runs_dir.empty()) continue;
        char name[64];
        std::snprintf(name, sizeof(name), "/v%03zu_seed%zu", i, k);
        dirs.push_back(o.runs_dir + "/" + std::filesystem::path(files[f]).stem().string() + name);
      }
    }
  }
  const std::vector<SweepRun> runs = RunSweepPoints(tasks, dirs, threads);
  std::vector<SweepRow> rows(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    rows[i].value = values[i];
    rows[i].points.resize(nf);
    for (size_t f = 0; f < nf; ++f) {
      for (size_t k = 0; k < ns; ++k) rows[i].points[f].seeds.push_back(runs[(i * nf + f) * ns + k]);
      rows[i].results.push_back(rows[i].points[f].seeds[0].result);
    }
  }
  return rows;
}

std::string WriteSweep(const std::string& dir, const std::vector<std::string>& files,
                       const SweepOptions& o, const std::vector<SweepRow>& rows) {
  std::filesystem::create_directories(dir);
  std::string csv = o.key;
  std::vector<std::string> names;
  for (const auto& f : files) names.push_back(std::filesystem::path(f).stem().string());
  for (const auto& n : names) {
    csv += "," + n + "_distance_m," + n + "_speed_mps," + n + "_mean_speed_mps," + n + "_fell," +
           n + "_fall_time_s," + n + "_stalled," + n + "_stall_time_s";
  }
  csv += "\n";
  const auto time = [](double t) { return t < 0 ? std::string() : sim::ExactNumber(t); };
  for (const SweepRow& r : rows) {
    csv += sim::ExactNumber(r.value);
    for (const SweepPoint& p : r.points) {
      csv += "," + sim::ExactNumber(p.worst_distance_m()) + "," +
             sim::ExactNumber(p.worst_speed_mps()) + "," + sim::ExactNumber(p.mean_speed_mps()) +
             "," + std::to_string(p.fell()) + "," + time(p.first_fall_s()) + "," +
             std::to_string(p.stalled()) + "," + time(p.first_stall_s());
    }
    csv += "\n";
  }
  common::WriteFileAtomic(dir + "/sweep.csv", csv);
  return common::RunGnuplot(dir, SweepScript(o, names), {"sweep.png"});
}

}  // namespace climbsim::optimise
