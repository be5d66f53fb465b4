#include <algorithm>
#include <atomic>
#include <filesystem>
#include <cmath>
#include <thread>

#include "optimise/optimise.h"
#include "sim/gnuplot.h"

namespace climbsim::optimise {

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
      try {
        SetDottedKey(tree, o.key, v);
      } catch (const std::invalid_argument& e) {
        throw InputError(files[f], 0, 0, o.key, e.what());
      }
      try {
        scenarios[f].push_back(sim::ParseScenario(tree, files[f]));
      } catch (const InputError& e) {
        throw InputError(files[f], 0, 0, o.key,
                         o.key + " = " + sim::ExactNumber(v) + " gives an invalid scenario: " +
                             e.key() + " " + e.message());
      }
    }
  }

  std::vector<SweepRow> rows(values.size());
  for (size_t i = 0; i < values.size(); ++i) {
    rows[i].value = values[i];
    rows[i].results.resize(files.size());
  }
  // Tasks in a fixed order, each writing its own slot: results do not depend on threads.
  const int tasks = static_cast<int>(values.size() * files.size());
  std::atomic<int> next{0};
  auto worker = [&] {
    ModelCache cache;
    for (int t = next++; t < tasks; t = next++) {
      const size_t f = t % files.size(), i = t / files.size();
      sim::Simulation run(scenarios[f][i], cache.For(scenarios[f][i]));
      rows[i].results[f] = run.Run();
    }
  };
  const int threads = std::max(
      1, std::min(tasks, o.threads > 0 ? o.threads
                                       : static_cast<int>(std::thread::hardware_concurrency())));
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
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
  sim::WriteFileAtomic(dir + "/sweep.csv", csv);
  std::string plots;
  for (size_t f = 0; f < files.size(); ++f) {
    const int col = 3 + 4 * static_cast<int>(f);
    const std::string fell = "(column(" + std::to_string(col + 1) + ") > 0.5)";
    plots += std::string(f ? ", " : "") + "data using 1:(" + fell + " ? NaN : 100*column(" +
             std::to_string(col) + ")) with linespoints lw 2 lc " + std::to_string(f + 1) +
             " title '" + names[f] + "', data using 1:(" + fell +
             " ? 0 : NaN) with points pt 2 ps 2 lc " + std::to_string(f + 1) + " title '" +
             names[f] + " fell'";
  }
  const std::string script =
      "set terminal pngcairo size 900,560 noenhanced\nset output OUTPUT(0)\n"
      "set datafile separator ','\nset key top right\nset grid\n"
      "set title 'climbsim sweep: mean speed along the travel direction'\n"
      "set xlabel " + sim::GnuplotQuote(o.key) + "\nset ylabel 'speed [cm/s]'\n"
      "data = " + sim::GnuplotQuote(dir + "/sweep.csv") + "\n"
      "plot " + plots + "\n";
  return sim::RunGnuplot(script, {dir + "/sweep.png"});
}

}  // namespace climbsim::optimise
