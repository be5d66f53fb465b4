#include <algorithm>
#include <filesystem>
#include <cmath>
#include <stdexcept>

#include "optimise/comm.h"
#include "optimise/text.h"
#include "experiments/experiments.h"
#include "common/common.h"

namespace climbsim::optimise {
namespace {

nlohmann::json ToJson(const sim::RunResult& r) {
  return {r.stable, r.failure, r.steps, r.sim_time_s, r.wall_time_s, r.fell,
          r.fall_time_s, r.distance_m, r.heading_deg, r.actuator_work_j};
}

sim::RunResult FromJson(const nlohmann::json& j) {
  sim::RunResult r;
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
  return r;
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

}  // namespace

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
}

std::string SweepTable(const std::vector<std::string>& files, const SweepOptions& o,
                       const std::vector<SweepRow>& rows, const std::string& out_dir,
                       const std::string& warning) {
  std::string out;
  Appendf(&out, "%12s", o.key.c_str());
  for (const auto& f : files) {
    Appendf(&out, "  %26s", std::filesystem::path(f).stem().string().c_str());
  }
  Appendf(&out, "\n%12s", "");
  for (size_t f = 0; f < files.size(); ++f) {
    Appendf(&out, "  %14s %11s", "speed [cm/s]", "fell at [s]");
  }
  Appendf(&out, "\n");
  for (const auto& r : rows) {
    Appendf(&out, "%12g", r.value);
    for (const auto& res : r.results) {
      const double v = res.mean_speed_mps();
      if (res.fell) {
        Appendf(&out, "  %14s %11.2f", "-", res.fall_time_s);
      } else {
        Appendf(&out, "  %14.2f %11s", 100 * v, "-");
      }
    }
    Appendf(&out, "\n");
  }
  Appendf(&out, "  outputs %s/{sweep.csv,sweep.png}%s%s\n", out_dir.c_str(),
          warning.empty() ? "" : "  (plot: ", warning.empty() ? "" : (warning + ")").c_str());
  return out;
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

  std::vector<SweepRow> rows(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    rows[i].value = values[i];
    rows[i].results.resize(files.size());
  }
  // Tasks in a fixed order, each writing its own slot: results do not depend on threads.
  // Under mpirun, task t runs on rank t mod N and the ranks exchange their results.
  const Comm& comm = Comm::World();
  const int all = static_cast<int>(values.size() * files.size());
  std::vector<int> mine;
  for (int t = comm.rank(); t < all; t += comm.size()) mine.push_back(t);
  ParallelRollouts(static_cast<int>(mine.size()), threads, [&](int m, ModelCache& cache) {
    const int t = mine[m];
    const size_t f = t % files.size(), i = t / files.size();
    sim::Simulation run(scenarios[f][i], cache.For(scenarios[f][i]));
    rows[i].results[f] = run.Run();
  });
  if (comm.size() > 1) {
    nlohmann::json local = nlohmann::json::array();
    for (int t : mine) {
      local.push_back({t, ToJson(rows[t / files.size()].results[t % files.size()])});
    }
    for (const std::string& part : comm.AllGather(local.dump())) {
      for (const auto& entry : nlohmann::json::parse(part)) {
        const int t = entry[0].get<int>();
        rows[t / files.size()].results[t % files.size()] = FromJson(entry[1]);
      }
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
    csv += "," + n + "_distance_m," + n + "_speed_mps," + n + "_fell," + n + "_fall_time_s";
  }
  csv += "\n";
  for (const SweepRow& r : rows) {
    csv += sim::ExactNumber(r.value);
    for (const sim::RunResult& res : r.results) {
      csv += "," + sim::ExactNumber(res.distance_m) + "," + sim::ExactNumber(res.mean_speed_mps()) +
             "," + (res.fell ? "1" : "0") + "," +
             (res.fell ? sim::ExactNumber(res.fall_time_s) : "");
    }
    csv += "\n";
  }
  common::WriteFileAtomic(dir + "/sweep.csv", csv);
  std::string plots;
  for (size_t f = 0; f < files.size(); ++f) {
    const int col = 3 + 4 * static_cast<int>(f);
    const std::string fell = "(column(" + std::to_string(col + 1) + ") > 0.5)";
    plots += std::string(f ? ", " : "") + "data using 1:(" + fell + " ? NaN : 100*column(" +
             std::to_string(col) + ")) with linespoints lw 2 lc " + std::to_string(f + 1) +
             " title " + common::GnuplotQuote(names[f]) + ", data using 1:(" + fell +
             " ? 0 : NaN) with points pt 2 ps 2 lc " + std::to_string(f + 1) + " title " +
             common::GnuplotQuote(names[f] + " fell");
  }
  const std::string script =
      "set terminal pngcairo size 900,560 noenhanced\nset output OUTPUT(0)\n"
      "set datafile separator ','\nset key top right\nset grid\n"
      "set title 'climbsim sweep: mean speed along the travel direction'\n"
      "set xlabel " + common::GnuplotQuote(o.key) + "\nset ylabel 'speed [cm/s]'\n"
      "data = 'sweep.csv'\n"  // gnuplot runs in `dir`
      "plot " + plots + "\n";
  return common::RunGnuplot(dir, script, {"sweep.png"});
}

}  // namespace climbsim::optimise
