// climbsim sweep --find: bisects one key for the edge of a condition on the runs' summaries
// (experiments/experiments.h states the grammar and the result).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "common/common.h"
#include "experiments/experiments.h"
#include "optimise/comm.h"
#include "optimise/disturbance.h"
#include "optimise/text.h"

namespace climbsim::optimise {
namespace {

InputError Bad(const char* flag, const std::string& m) {
  return InputError("climbsim sweep", 0, 0, flag, m);
}

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  const size_t b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// One term, FIELD OP NUMBER: the field a run of letters, digits and '_' (summary.json's top
// level), the number read whole by strtod.
Condition::Term ParseTerm(const std::string& text) {
  const std::string t = Trim(text);
  size_t i = 0;
  while (i < t.size() && (std::isalnum(static_cast<unsigned char>(t[i])) || t[i] == '_')) ++i;
  const std::string field = t.substr(0, i);
  while (i < t.size() && t[i] == ' ') ++i;
  std::string op;
  for (const char* o : {"<=", ">=", "==", "!=", "<", ">"}) {
    if (t.compare(i, std::string(o).size(), o) == 0) {
      op = o;
      break;
    }
  }
  const std::string number = Trim(t.substr(std::min(t.size(), i + op.size())));
  char* end = nullptr;
  const double value = number.empty() ? 0.0 : std::strtod(number.c_str(), &end);
  if (field.empty() || std::isdigit(static_cast<unsigned char>(field[0])) || op.empty() ||
      number.empty() || end != number.c_str() + number.size() || !std::isfinite(value)) {
    throw Bad("--condition", "'" + t +
                                 "' is not FIELD OP NUMBER (a summary.json field, one of < <= > "
                                 ">= == !=, a number), e.g. distance_m>=0.1");
  }
  return {field, op, value};
}

bool Compare(double a, const std::string& op, double b) {
  if (op == "<") return a < b;
  if (op == "<=") return a <= b;
  if (op == ">") return a > b;
  if (op == ">=") return a >= b;
  if (op == "==") return a == b;
  return a != b;
}

// Whether every seed of the point meets the condition; the first that does not in *failing.
bool PointHolds(const Condition& c, const SweepPoint& p, std::string* failing) {
  for (size_t k = 0; k < p.seeds.size(); ++k) {
    std::string why;
    if (!Meets(c, p.seeds[k].summary, &why)) {
      *failing = "seed " + std::to_string(k) + ": " + why;
      return false;
    }
  }
  return true;
}

}  // namespace

Condition ParseCondition(const std::string& text) {
  Condition c;
  c.text = text;
  size_t from = 0;
  for (;;) {
    const size_t at = text.find(" and ", from);
    c.terms.push_back(ParseTerm(text.substr(from, at == std::string::npos ? at : at - from)));
    if (at == std::string::npos) break;
    from = at + 5;
  }
  return c;
}

bool Meets(const Condition& c, const nlohmann::json& summary, std::string* why) {
  for (const Condition::Term& t : c.terms) {
    const auto it = summary.find(t.field);
    double v = 0.0;
    if (it != summary.end() && it->is_boolean()) {
      v = it->get<bool>() ? 1.0 : 0.0;
    } else if (it != summary.end() && it->is_number()) {
      v = it->get<double>();
    } else {
      throw Bad("--condition", "summary.json has no number or true/false '" + t.field + "'");
    }
    if (!Compare(v, t.op, t.value)) {
      if (why) *why = t.field + " = " + sim::ExactNumber(v);
      return false;
    }
  }
  return true;
}

namespace {

// The threshold search's state: the scenario tree, and each probe's runs.
class Finder {
 public:
  Finder(const std::string& file, const FindOptions& o) : file_(file), o_(o) {
    root_ = sim::LoadYamlFile(file);
    sim::ParseScenario(root_, file);
    threads_ = o.threads > 0 ? o.threads : DefaultThreads();
    Scenario(o.low);  // both ends build before anything runs (bad input: exit 2)
    Scenario(o.high);
  }

  sim::Scenario Scenario(double v) const {
    YAML::Node tree = YAML::Clone(root_);
    try {
      SetDottedKey(tree, o_.key, v);
    } catch (const std::invalid_argument& e) {
      throw InputError(file_, 0, 0, o_.key, e.what());
    }
    try {
      sim::Scenario s = sim::ParseScenario(tree, file_);
      ModelCache cache;
      sim::Simulation check(s, cache.For(s));
      return s;
    } catch (const InputError& e) {
      throw InputError(file_, 0, 0, o_.key,
                       o_.key + " = " + sim::ExactNumber(v) + " gives an invalid scenario: " +
                           e.key() + " " + e.message());
    }
  }

  // Runs the point at v on every seed (in parallel) and records the probe.
  const FindProbe& Probe(double v) {
    const sim::Scenario s = Scenario(v);
    std::vector<sim::Scenario> runs;
    std::vector<std::string> dirs;
    for (int k = 0; k < o_.seeds; ++k) {
      runs.push_back(s);
      ApplyCaseSeed(&runs.back(), k);
      if (!o_.runs_dir.empty()) {
        char name[64];
        std::snprintf(name, sizeof(name), "/probe%02zu_seed%d", probes_.size(), k);
        dirs.push_back(o_.runs_dir + name);
      }
    }
    FindProbe p;
    p.value = v;
    p.point.seeds = RunSweepPoints(runs, dirs, threads_);
    p.holds = PointHolds(o_.condition, p.point, &p.failing);
    probes_.push_back(std::move(p));
    return probes_.back();
  }

  std::vector<FindProbe> TakeProbes() { return std::move(probes_); }

 private:
  std::string file_;
  const FindOptions& o_;
  YAML::Node root_;
  int threads_ = 1;
  std::vector<FindProbe> probes_;
};

// Probes sorted by value whose outcome differs from the next one's.
int Flips(std::vector<FindProbe> probes) {
  std::sort(probes.begin(), probes.end(),
            [](const FindProbe& a, const FindProbe& b) { return a.value < b.value; });
  int flips = 0;
  for (size_t i = 1; i < probes.size(); ++i) flips += probes[i].holds != probes[i - 1].holds;
  return flips;
}

}  // namespace

FindResult FindThreshold(const std::string& file, const FindOptions& o) {
  if (!std::isfinite(o.low) || !std::isfinite(o.high) || !(o.low < o.high)) {
    throw Bad("--high", "must be a finite number above --low");
  }
  if (o.seeds < 1 || o.seeds > kMaxSweepSeeds) {
    throw Bad("--seeds", "must be in [1, " + std::to_string(kMaxSweepSeeds) + "]");
  }
  if (!o.runs_dir.empty() && ProcessCount() > 1) {
    throw Bad("--keep-runs", "keeps run folders in one process only (not under mpirun)");
  }
  const auto t0 = std::chrono::steady_clock::now();
  Finder finder(file, o);
  const bool low_holds = finder.Probe(o.low).holds;
  const bool high_holds = finder.Probe(o.high).holds;
  if (low_holds == high_holds) {
    throw Bad("--condition", "'" + o.condition.text + "' " +
                                 (low_holds ? "holds" : "fails") + " on every seed at both " +
                                 o.key + " = " + sim::ExactNumber(o.low) + " and " +
                                 sim::ExactNumber(o.high) +
                                 ": no edge between them (widen --low/--high)");
  }
  // Bisection: a holds, b fails, whichever side each is on.
  double a = low_holds ? o.low : o.high, b = low_holds ? o.high : o.low;
  while (std::abs(b - a) > o.tolerance * std::max(std::abs(a), std::abs(b))) {
    const double c = 0.5 * (a + b);
    (finder.Probe(c).holds ? a : b) = c;
  }
  FindResult r;
  r.holds_at = a;
  r.fails_at = b;
  r.probes = finder.TakeProbes();
  r.flips = Flips(r.probes);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

void WriteFind(const std::string& dir, const FindOptions& o, const FindResult& r) {
  std::filesystem::create_directories(dir);
  std::string csv = "probe," + o.key +
                    ",holds,worst_distance_m,worst_speed_mps,mean_speed_mps,fell,stalled,failing\n";
  for (size_t i = 0; i < r.probes.size(); ++i) {
    const FindProbe& p = r.probes[i];
    std::string failing = "\"";
    for (char ch : p.failing) failing += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    csv += std::to_string(i) + "," + sim::ExactNumber(p.value) + "," + (p.holds ? "1" : "0") +
           "," + sim::ExactNumber(p.point.worst_distance_m()) + "," +
           sim::ExactNumber(p.point.worst_speed_mps()) + "," +
           sim::ExactNumber(p.point.mean_speed_mps()) + "," + std::to_string(p.point.fell()) +
           "," + std::to_string(p.point.stalled()) + "," + failing + "\"\n";
  }
  common::WriteFileAtomic(dir + "/find.csv", csv);
}

std::string FindText(const FindOptions& o, const FindResult& r) {
  std::string out;
  Appendf(&out, "climbsim sweep --find %s: '%s' on every one of %d seed%s\n", o.key.c_str(),
          o.condition.text.c_str(), o.seeds, o.seeds == 1 ? "" : "s");
  Appendf(&out, "  %5s %14s %6s %13s  %s\n", "probe", o.key.c_str(), "holds", "worst dist [m]",
          "first failing seed");
  for (size_t i = 0; i < r.probes.size(); ++i) {
    const FindProbe& p = r.probes[i];
    Appendf(&out, "  %5zu %14.6g %6s %13.4f  %s\n", i, p.value, p.holds ? "yes" : "no",
            p.point.worst_distance_m(), p.failing.c_str());
  }
  Appendf(&out, "edge: holds at %s = %.6g, fails at %.6g (%.2g %% apart); %zu probes, %d runs, "
                "%.1f s\n",
          o.key.c_str(), r.holds_at, r.fails_at,
          100 * std::abs(r.fails_at - r.holds_at) /
              std::max(std::abs(r.holds_at), std::abs(r.fails_at)),
          r.probes.size(), static_cast<int>(r.probes.size()) * o.seeds, r.wall_s);
  if (r.flips > 1) {
    Appendf(&out, "  not monotone: sorted by %s, the probes change outcome %d times; the edge "
                  "above is one of them (find.csv lists every probe)\n",
            o.key.c_str(), r.flips);
  }
  return out;
}

}  // namespace climbsim::optimise
