#include "experiments/bench_verbs.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "common/common.h"
#include "experiments/bench_speed.h"
#include "optimise/schedule.h"
#include "optimise/text.h"
#include "scenario/dotted_key.h"
#include "sim/sim.h"

namespace climbsim::optimise {
namespace {

// The profile part of bench speed's text: time inside each part of the step.
std::string ProfileText(const sim::SpeedReport& r) {
  std::string out;
  double effects = 0.0;
  for (const auto& e : r.effect_s) effects += e.second;
  if (r.profile_from_s > 0) {
    Appendf(&out, "  profile of the full scenario from %g s (%ld steps; time inside each part of "
            "the step):\n", r.profile_from_s, r.profiled_steps);
  } else {
    Appendf(&out, "  profile of the full scenario (time inside each part of the step):\n");
  }
  Appendf(&out, "    (less the profile's own clock, %.0f ns a lap, once per part and call)\n",
          1e9 * r.clock_lap_s);
  // Names as wide as the longest one (the controller's: cpg+reflex+transition).
  int w = 14;
  for (const auto& e : r.effect_s) w = std::max(w, static_cast<int>(e.first.size()));
  Appendf(&out, "    %-*s %9.3f s\n", w, "mj_step", r.mj_step_s);
  for (const auto& e : r.effect_s) {
    Appendf(&out, "    %-*s %9.3f s  %+6.2f%% of mj_step\n", w, e.first.c_str(), e.second,
            100 * e.second / r.mj_step_s);
  }
  Appendf(&out, "    %-*s %9.3f s  %+6.2f%% of mj_step\n", w, "monitor", r.monitor_s,
          100 * r.monitor_s / r.mj_step_s);
  Appendf(&out, "    %-*s %9.3f s  %+6.2f%% of mj_step\n", w, "all effects", effects,
          100 * effects / r.mj_step_s);
  Appendf(&out, "    (with the clock left in: all effects %+.2f%% of mj_step)\n",
          100 * r.effects_with_clock_s / r.mj_step_with_clock_s);
  return out;
}

// The scenario's YAML tree with each KEY=VALUE of --versus set; *label joins them.
YAML::Node VersusTree(const std::string& file, const std::vector<std::string>& versus,
                      std::string* label) {
  YAML::Node tree = sim::LoadYamlFile(file);
  for (const std::string& kv : versus) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      throw InputError("--versus", 0, 0, kv,
                       "expected KEY=VALUE, e.g. physics.integrator=implicit");
    }
    // The dotted key's message says which part does not fit; the KEY=VALUE says where.
    try {
      SetDottedKeyText(tree, kv.substr(0, eq), kv.substr(eq + 1));
    } catch (const std::invalid_argument& e) {
      throw InputError("--versus", 0, 0, kv, e.what());
    }
    *label += (label->empty() ? "" : " ") + kv;
  }
  return tree;
}

// CPU seconds (user + system) of this process and, separately, of the children it waited for.
double CpuSeconds(int who) {
  rusage u{};
  getrusage(who, &u);
  return u.ru_utime.tv_sec + 1e-6 * u.ru_utime.tv_usec + u.ru_stime.tv_sec +
         1e-6 * u.ru_stime.tv_usec;
}

double LoadAverage() {
  double load = 0.0;
  std::ifstream("/proc/loadavg") >> load;
  return load;
}

// The options of one of bench optimise's runs in `dir`: an earlier bench's run is replaced
// whole, anything else a user has there is refused.
sim::RunFolderOptions BenchRunFolder(const std::string& dir, const std::string& file) {
  return {
      .made_by = "optimise", .force = sim::RunFolderMadeBy(dir) == "optimise", .inputs = {file}};
}

// One MPI run: `climbsim optimise` under mpirun, from an argument vector (no shell). Returns
// "" or why it failed.
std::string MpiRun(const std::string& exe, const std::string& file, int evaluations,
                   const std::string& dir, int ranks) {
  std::vector<std::string> argv = {"mpirun", "-np", std::to_string(ranks), "--oversubscribe"};
  // Open MPI refuses root unless told (containers and CI often run as root).
  if (geteuid() == 0) argv.push_back("--allow-run-as-root");
  argv.insert(argv.end(), {exe, "optimise", file, "--out", dir, "--max-evaluations",
                           std::to_string(evaluations), "--threads", "1", "--quiet"});
  if (BenchRunFolder(dir, file).force) argv.push_back("--force");  // an earlier bench's run
  // The ranks read the file as this process did: with its --set.
  for (const sim::KeyOverride& o : sim::CommandLineKeys()) {
    argv.insert(argv.end(), {"--set", o.key + "=" + o.value});
  }
  return common::RunProcess(argv, {.stdout_path = ""});
}

// The queue orders bench optimise's schedule simulation compares.
enum class Order {
  kAsQueued,           // as the run queued them: longest predicted first
  kCandidate,          // candidate by candidate, run by run (the order before prediction)
  kKnownLongestFirst,  // longest first by the recorded times: the best a prediction can do
  kNoBarrier,          // every rollout in one batch, longest first: what the barriers cost
};

// An optimise run's recorded rollouts as a schedule (optimise/schedule.h): a chain of
// batches per start, gated by start 0's first evaluation as Evaluator::Submit gates them.
Schedule OptimiseSchedule(const Result& r, Order order) {
  Schedule s;
  std::vector<double> all_s;
  for (const BatchRecord& b : r.batches) {
    if (static_cast<int>(s.chains.size()) <= b.start) s.chains.resize(b.start + 1);
    std::vector<int> slots = b.order;
    if (order == Order::kCandidate) std::sort(slots.begin(), slots.end());
    if (order == Order::kKnownLongestFirst) {
      std::stable_sort(slots.begin(), slots.end(),
                       [&](int a, int c) { return b.wall_s[a] > b.wall_s[c]; });
    }
    ScheduleBatch batch;
    for (int slot : slots) batch.jobs.push_back({b.wall_s[slot]});
    for (int slot : slots) all_s.push_back(b.wall_s[slot]);
    s.chains[b.start].push_back(std::move(batch));
  }
  s.gate_chain = 0;
  s.gated_from_batch = 1;
  if (order == Order::kNoBarrier) {
    std::sort(all_s.rbegin(), all_s.rend());
    ScheduleBatch one;
    for (double t : all_s) one.jobs.push_back({t});
    s = Schedule{};
    s.chains = {{one}};
  }
  return s;
}

// "busy share per thread: 98.2 % 97.9 % of the 41.3 s the workers served the queue".
std::string BusyLine(const std::vector<double>& busy_s, double wall_s) {
  std::string line = "    busy share per thread (time in rollouts / wall):";
  for (double b : busy_s) Appendf(&line, " %.1f %%", wall_s > 0 ? 100.0 * b / wall_s : 0.0);
  Appendf(&line, " of the %.1f s the workers ran\n", wall_s);
  return line;
}

// The predicted speed-ups on 2 to 16 cores from one run's recorded rollout times.
std::string PredictionText(const Result& r) {
  int rollouts = 0;
  for (const BatchRecord& b : r.batches) rollouts += static_cast<int>(b.order.size());
  std::string out;
  Appendf(&out, "  predicted speed-up on N cores (schedule simulation of the %zu batches, %d "
          "rollouts, of the 1-thread run):\n", r.batches.size(), rollouts);
  const std::pair<Order, const char*> rows[] = {
      {Order::kAsQueued, "as queued (longest predicted first)"},
      {Order::kCandidate, "candidate order"},
      {Order::kKnownLongestFirst, "longest first, times known"},
      {Order::kNoBarrier, "no generation barrier (bound)"}};
  for (const auto& [order, name] : rows) {
    Appendf(&out, "    %-38s %s\n", name, SpeedupLine(OptimiseSchedule(r, order)).c_str());
  }
  return out;
}

// bench optimise with 1 and 2 threads in this process.
void ThreadRuns(const std::string& file, int evaluations, const std::string& out,
                const std::function<void(const std::string&)>& print) {
  double rate[2] = {0, 0};
  double predicted_2 = 0.0;
  for (int threads : {1, 2}) {
    Options o;
    o.out_dir = out + "/threads" + std::to_string(threads);
    o.force = BenchRunFolder(o.out_dir, file).force;  // an earlier bench's run
    o.threads = threads;
    o.max_evaluations = evaluations;
    const double cpu0 = CpuSeconds(RUSAGE_SELF);
    const Result r = Optimise(file, o);
    const double cpu = CpuSeconds(RUSAGE_SELF) - cpu0;
    rate[threads - 1] = r.evaluations_computed / r.wall_time_s;
    std::string line;
    Appendf(&line, "  --threads %d: %.2f evaluations/s (%d in %.1f s, CPU %.1f s, load %.1f), "
            "best J %.6f\n",
            threads, rate[threads - 1], r.evaluations_computed, r.wall_time_s, cpu,
            LoadAverage(), r.best.objective);
    line += BusyLine(r.worker_busy_s, r.serve_wall_s);
    if (threads == 1) {
      line += PredictionText(r);
      predicted_2 = PredictedSpeedups(OptimiseSchedule(r, Order::kAsQueued), {2})[0];
    }
    print(line);
  }
  std::string line;
  Appendf(&line, "  speed-up with 2 threads: %.2fx (predicted %.2fx)\n", rate[1] / rate[0],
          predicted_2);
  print(line);
}

// The same optimisation as 1 and 2 MPI ranks of one thread each (mpirun from PATH).
void MpiRuns(const std::string& exe, const std::string& file, int evaluations,
             const std::string& out, const std::function<void(const std::string&)>& print) {
  double mpi_rate[2] = {0, 0};
  for (int ranks : {1, 2}) {
    const std::string dir = out + "/mpi" + std::to_string(ranks);
    const double cpu0 = CpuSeconds(RUSAGE_CHILDREN);
    const std::string error = MpiRun(exe, file, evaluations, dir, ranks);
    if (!error.empty()) throw std::runtime_error("bench optimise: mpirun failed: " + error);
    const double cpu = CpuSeconds(RUSAGE_CHILDREN) - cpu0;
    std::ifstream in(dir + "/summary.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    mpi_rate[ranks - 1] = j["evaluations_per_s"].get<double>();
    std::string line;
    Appendf(&line, "  mpirun -np %d --threads 1: %.2f evaluations/s (%d in %.1f s, CPU %.1f s, "
            "load %.1f), best J %.6f\n",
            ranks, mpi_rate[ranks - 1], j["evaluations_computed"].get<int>(),
            j["wall_time_s"].get<double>(), cpu, LoadAverage(),
            j["best_objective"].get<double>());
    print(line);
  }
  std::string line;
  Appendf(&line, "  speed-up with 2 MPI ranks: %.2fx\n", mpi_rate[1] / mpi_rate[0]);
  print(line);
}

// A bench robustness run's recorded cases as a schedule (optimise/schedule.h): the
// undisturbed runs gate every search, a chain of bisection steps each, a step decided at its
// first failure. A case this run dropped (after a failure) gets the step's longest recorded
// time: more cores would start it, and it would keep a core busy that long.
Schedule RobustnessSchedule(const RobustnessReport& r, bool lowest_index_first) {
  Schedule s;
  s.lowest_index_first = lowest_index_first;
  const auto batch = [](const RobustnessStepRecord& step, bool stop_at_failure) {
    ScheduleBatch b;
    b.stop_at_failure = stop_at_failure;
    double longest_s = 0.0;
    for (size_t i = 0; i < step.wall_s.size(); ++i) {
      if (step.ran[i]) longest_s = std::max(longest_s, step.wall_s[i]);
    }
    for (size_t i = 0; i < step.wall_s.size(); ++i) {
      b.jobs.push_back({step.ran[i] ? step.wall_s[i] : longest_s, step.failed[i] != 0});
    }
    return b;
  };
  s.chains.push_back({batch(r.baselines, false)});
  for (const auto& search : r.searches) {
    s.chains.emplace_back();
    for (const RobustnessStepRecord& step : search) s.chains.back().push_back(batch(step, true));
  }
  s.gate_chain = 0;
  s.gated_from_batch = 0;
  return s;
}

}  // namespace

std::string RunBenchSpeed(const std::string& file, double duration_s, int repetitions,
                          double profile_from_s) {
  if (profile_from_s >= duration_s) {
    throw InputError("climbsim bench speed", 0, 0, "--profile-from",
                     "must be less than --duration (" + std::to_string(duration_s) + " s)");
  }
  const sim::Scenario s = sim::LoadScenario(file);
  const sim::SpeedReport r = sim::BenchSpeed(s, duration_s, repetitions, profile_from_s);
  std::string out;
  Appendf(&out, "climbsim bench speed: %s, %ld steps per run, %d repetitions, interleaved\n",
          file.c_str(), r.steps, r.repetitions);
  Appendf(&out, "  %-16s %14s %12s %s\n", "variant", "steps/s", "vs bare", "(median; each run)");
  for (const auto& v : r.variants) {
    Appendf(&out, "  %-16s %14.0f %+11.1f%%  (", v.name.c_str(), v.median_steps_per_s,
            100 * v.overhead);
    for (size_t k = 0; k < v.steps_per_s.size(); ++k) {
      Appendf(&out, "%s%.0f", k ? " " : "", v.steps_per_s[k]);
    }
    Appendf(&out, ")\n");
  }
  return out + ProfileText(r);
}

std::string RunBenchSpeedVersus(const std::string& file, const std::vector<std::string>& versus,
                                double duration_s, int repetitions) {
  const sim::Scenario a = sim::LoadScenario(file);
  std::string label;
  const YAML::Node tree = VersusTree(file, versus, &label);
  const sim::Scenario b = sim::ParseScenario(tree, file + " with --versus " + label);
  const sim::SpeedComparison c = sim::BenchSpeedCompare(a, b, duration_s, repetitions);
  std::string out;
  Appendf(&out, "climbsim bench speed: %s, every effect on, %d repetitions, interleaved A B A B\n",
          file.c_str(), repetitions);
  Appendf(&out, "  %-3s %-44s %12s %10s %s\n", "", "setting", "steps/s", "distance",
          "(each run)");
  auto side = [&](const char* name, const std::string& what,
                  const sim::SpeedComparison::Side& s) {
    Appendf(&out, "  %-3s %-44s %12.0f %9.4fm%s (", name, what.c_str(), s.median_steps_per_s,
            s.distance_m, s.fell ? " fell" : (s.stable ? "" : " unstable"));
    for (size_t k = 0; k < s.steps_per_s.size(); ++k) {
      Appendf(&out, "%s%.0f", k ? " " : "", s.steps_per_s[k]);
    }
    Appendf(&out, ")\n");
  };
  side("A", "as written", c.a);
  side("B", label, c.b);
  Appendf(&out, "  A runs %.2fx the steps/s of B (%ld vs %ld steps per run)\n", c.ratio,
          c.a.steps, c.b.steps);
  return out;
}

std::string RunBenchAccuracy(const std::string& file, double duration_s, int threads,
                             const std::string& out) {
  // A run folder (docs/run-folders.md), checked before the runs; an earlier bench's replaced.
  sim::RunFolder folder(out, {.made_by = "bench accuracy",
                              .force = sim::RunFolderMadeBy(out) == "bench accuracy",
                              .inputs = {file}});
  const AccuracyReport r = BenchAccuracy(file, duration_s, threads);
  const std::string warning = WriteAccuracy(folder.path(), r);
  folder.Commit();
  std::string text;
  Appendf(&text, "climbsim bench accuracy: %s, %.1f s simulated per run\n", file.c_str(),
          r.duration_s);
  Appendf(&text, "  reference (finest of every knob): %.4f m climbed in %.2f s wall%s\n",
          r.reference.distance_m, r.reference.wall_s, r.reference.fell ? ", fell" : "");
  Appendf(&text, "  %-18s %-14s %8s %12s %12s %6s %10s %10s\n", "knob", "setting", "wall [s]",
          "dist err [m]", "detach [s]", "n diff", "peak load", "pull-off");
  for (const auto& row : r.rows) {
    Appendf(&text, "  %-18s %-14s %8.2f %12.2e %12.2e %6d %10.2e %10.2e%s\n", row.knob.c_str(),
            row.setting.c_str(), row.run.wall_s, row.distance_error_m, row.detach_time_error_s,
            row.detach_count_diff, row.peak_load_error, row.pulloff_error,
            row.run.fell ? "  fell" : "");
  }
  Appendf(&text, "  outputs %s/{accuracy.csv,accuracy.png}%s%s\n", out.c_str(),
          warning.empty() ? "" : "  plot: ", warning.c_str());
  return text;
}

void RunBenchOptimise(const std::string& file, int evaluations, const std::string& out,
                      const std::string& only, const std::string& climbsim_exe,
                      const std::function<void(const std::string&)>& print) {
  // The scenario and every output folder are checked before any work (and before anything in
  // a folder is replaced): bad input is exit 2 here, not a failed mpirun later.
  Problem problem(file);
  for (const char* sub : {"threads1", "threads2", "mpi1", "mpi2"}) {
    const std::string dir = out + "/" + sub;
    sim::CheckOutputFolder(dir, BenchRunFolder(dir, file));
  }
  std::string head;
  Appendf(&head, "climbsim bench optimise: %s, %d evaluations\n", file.c_str(), evaluations);
  print(head);
  if (only != "mpi") ThreadRuns(file, evaluations, out, print);
  if (only != "threads" && BuiltWithMpi() && !common::FindInPath("mpirun").empty()) {
    MpiRuns(climbsim_exe, file, evaluations, out, print);
  }
}

std::string RunBenchRobustness(const std::string& file, const RobustnessOptions& options,
                               const std::string& out,
                               const std::function<void(double)>& progress) {
  // A run folder (docs/run-folders.md), checked and locked before the runs; an earlier
  // bench's replaced.
  sim::RunFolder folder(
      out, {.made_by = "bench robustness",
            .force = sim::RunFolderMadeBy(out) == "bench robustness",
            .inputs = {file}});
  // Push times, families left out, a too-short duration: said before the runs (or refused).
  std::fputs(RobustnessPlanText(PlanRobustness(sim::LoadScenario(file), options)).c_str(), stderr);
  const RobustnessReport r = BenchRobustness(file, options, progress);
  const std::string warning = WriteRobustness(folder.path(), r);
  folder.Commit();
  std::string text = RobustnessTable(r);
  Appendf(&text, "  outputs %s/{robustness.csv,robustness.png}%s%s\n", out.c_str(),
          warning.empty() ? "" : "  plot: ", warning.c_str());
  const bool failed = std::any_of(r.rows.begin(), r.rows.end(), [](const RobustnessRow& row) {
    return !row.failing_scenario_yaml.empty();
  });
  if (failed) {
    Appendf(&text, "  failing cases %s/failing/FAMILY[_spindle_gto_off].yaml: `climbsim simulate "
            "FILE --out DIR` replays one\n", out.c_str());
  }
  text += BusyLine(r.worker_busy_s, r.wall_s);
  const Schedule s = RobustnessSchedule(r, true);
  int runs = 0;
  for (const auto& chain : s.chains) {
    for (const ScheduleBatch& b : chain) runs += static_cast<int>(b.jobs.size());
  }
  Appendf(&text, "  predicted speed-up on N cores (schedule simulation of this run's %zu "
          "searches, %d cases):\n", r.searches.size(), runs);
  Appendf(&text, "    %-38s %s\n", "as run (lowest case index first)", SpeedupLine(s).c_str());
  Appendf(&text, "    %-38s %s\n", "first come first served",
          SpeedupLine(RobustnessSchedule(r, false)).c_str());
  return text;
}

}  // namespace climbsim::optimise
