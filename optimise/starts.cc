// The starts of `climbsim optimise`: each start runs NLopt (StartRunner) or CMA-ES
// (CmaesStart) on its own thread from its own first point and hands its candidates to the
// evaluator (evaluator.h).
#include "optimise/starts.h"

#include <nlopt.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <random>

#include "common/common.h"
#include "optimise/checkpoint.h"

namespace climbsim::optimise::internal {
namespace {

nlopt::algorithm Algorithm(const std::string& name) {
  static const std::map<std::string, nlopt::algorithm> k{
      {"LN_SBPLX", nlopt::LN_SBPLX},     {"LN_NELDERMEAD", nlopt::LN_NELDERMEAD},
      {"LN_BOBYQA", nlopt::LN_BOBYQA},   {"LN_COBYLA", nlopt::LN_COBYLA},
      {"GN_CRS2_LM", nlopt::GN_CRS2_LM}, {"GN_ISRES", nlopt::GN_ISRES},
      {"GN_ESCH", nlopt::GN_ESCH}};
  return k.at(name);
}

// The first point of a start, in [0, 1] coordinates: start 0 at the given values, start s
// drawn uniformly in the bounds with a seed from `seed` and s.
std::vector<double> StartPoint(const Problem& problem, int start) {
  const sim::OptimiseParams& p = problem.params();
  const std::vector<double> lo = problem.lower(), hi = problem.upper();
  std::vector<double> x0 = problem.start();
  if (start > 0) {
    std::mt19937_64 rng(Fnv1a("start") ^ (static_cast<uint64_t>(p.seed) << 20) ^ start);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (size_t i = 0; i < x0.size(); ++i) x0[i] = lo[i] + u(rng) * (hi[i] - lo[i]);
  }
  std::vector<double> u0(x0.size());
  for (size_t i = 0; i < x0.size(); ++i) u0[i] = (x0[i] - lo[i]) / (hi[i] - lo[i]);
  return u0;
}

// One start with NLopt: its own NLopt object and seed; evaluations in a fixed order.
class StartRunner {
 public:
  StartRunner(const Problem& problem, int start, int budget, Evaluator& rounds)
      : problem_(problem), start_(start), budget_(budget), rounds_(rounds),
        lo_(problem.lower()), hi_(problem.upper()) {}

  void Run() {
    const sim::OptimiseParams& p = problem_.params();
    // NLopt's random numbers are per thread, and each start has its own thread.
    nlopt::srand(static_cast<unsigned long>(p.seed) * 1000003ul + start_);
    const std::vector<double> u0 = StartPoint(problem_, start_);
    if (p.algorithm == "chain") {
      const int global = std::max(1, static_cast<int>(std::lround(budget_ * p.global_share)));
      Stage(nlopt::GN_CRS2_LM, u0, std::min(global, budget_));
      if (count_ < budget_) Stage(Algorithm(p.local_algorithm), best_u_, budget_ - count_);
    } else {
      Stage(Algorithm(p.algorithm), u0, budget_);
    }
  }

 private:
  void Stage(nlopt::algorithm algorithm, std::vector<double> u, int evaluations) {
    const sim::OptimiseParams& p = problem_.params();
    const unsigned n = static_cast<unsigned>(u.size());
    nlopt::opt opt(algorithm, n);
    opt.set_lower_bounds(std::vector<double>(n, 0.0));
    opt.set_upper_bounds(std::vector<double>(n, 1.0));
    opt.set_min_objective(&StartRunner::Trampoline, this);
    opt.set_maxeval(evaluations);
    // Coordinates are shares of each range, so an absolute tolerance is "share of range".
    if (p.xtol_rel > 0) opt.set_xtol_abs(p.xtol_rel);
    if (p.ftol_abs > 0) opt.set_ftol_abs(p.ftol_abs);
    if (p.max_time_s > 0) opt.set_maxtime(p.max_time_s);
    opt.set_initial_step(p.initial_step);
    double f = 0.0;
    try {
      opt.optimize(u, f);
    } catch (const std::exception&) {
      // Round-off limits and forced stops end the stage; the best point is kept below.
    }
  }

  static double Trampoline(const std::vector<double>& u, std::vector<double>& grad, void* self) {
    (void)grad;  // derivative-free algorithms only
    return static_cast<StartRunner*>(self)->Objective(u);
  }

  double Objective(const std::vector<double>& u) {
    std::vector<double> x(u.size());
    for (size_t i = 0; i < u.size(); ++i) {
      x[i] = lo_[i] + std::clamp(u[i], 0.0, 1.0) * (hi_[i] - lo_[i]);
    }
    const Evaluation e = rounds_.Submit(start_, {x}).front();
    ++count_;
    if (e.objective < best_f_) {
      best_f_ = e.objective;
      best_u_ = u;
    }
    return e.objective;
  }

  const Problem& problem_;
  const int start_;
  const int budget_;
  Evaluator& rounds_;
  const std::vector<double> lo_, hi_;
  int count_ = 0;
  double best_f_ = std::numeric_limits<double>::infinity();
  std::vector<double> best_u_;
};

// ---- CMA-ES ----------------------------------------------------------------------------------
// pagmo's cmaes samples a generation and evaluates it one candidate after the other inside
// evolve(). To evaluate a generation in parallel, each generation is run twice: a copy of the
// algorithm (same state, same random engine) evolves with a problem that only records the
// points it is asked for; those are evaluated as one batch; then the algorithm itself
// evolves with a problem that serves the costs, checking that it asks for the same points
// bit for bit.
struct Oracle {
  bool recording = true;
  std::vector<std::vector<double>> asked;
  std::vector<double> answers;
  size_t next = 0;
};

struct CmaesProblem {
  std::shared_ptr<Oracle> oracle;
  unsigned dimension = 1;

  pagmo::vector_double fitness(const pagmo::vector_double& u) const {
    Oracle& o = *oracle;
    if (o.recording) {
      o.asked.push_back(u);
      return {0.0};
    }
    if (o.next >= o.answers.size() || o.asked[o.next] != u) {
      throw std::logic_error("cmaes asked for a point it had not sampled");
    }
    return {o.answers[o.next++]};
  }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    return {pagmo::vector_double(dimension, 0.0), pagmo::vector_double(dimension, 1.0)};
  }
};

class CmaesStart {
 public:
  CmaesStart(const Problem& problem, int start, int budget, Evaluator& rounds)
      : problem_(problem), start_(start), budget_(budget), rounds_(rounds),
        lo_(problem.lower()), hi_(problem.upper()) {}

  void Run() {
    const sim::OptimiseParams& p = problem_.params();
    const unsigned n = static_cast<unsigned>(lo_.size());
    const std::vector<double> u0 = StartPoint(problem_, start_);
    const unsigned lambda =
        p.population > 0 ? static_cast<unsigned>(p.population)
                         : std::max(5u, 4u + static_cast<unsigned>(std::floor(3.0 * std::log(n))));
    oracle_ = std::make_shared<Oracle>();
    seed_ = static_cast<unsigned>(p.seed) * 1000003u + static_cast<unsigned>(start_);
    // One generation per evolve(), the state kept between calls (memory), candidates clipped
    // to the bounds; ftol is off (the copies of the start tie), xtol in shares of the range.
    pagmo::cmaes cma(1u, -1, -1, -1, -1, p.sigma0, 0.0, p.xtol_rel, true, true, seed_);
    // The first generation's points do not depend on the start's cost (the population is λ
    // copies of the start, which tie): sampled with a stand-in cost, they are evaluated in
    // one batch with the start point (traced until the bound is known: evaluator.h), and
    // checked against the points sampled with the real cost below.
    std::vector<std::vector<double>> first;
    if (rounds_.traces() && 1 + static_cast<int>(lambda) <= budget_) {
      first = Probe(cma, Population(u0, 0.0, lambda, n));
    }
    std::vector<std::vector<double>> xs = {ToX(u0)};
    for (const auto& u : first) xs.push_back(ToX(u));
    std::vector<Evaluation> evals = rounds_.Submit(start_, xs);
    pagmo::population pop = Population(u0, evals.front().objective, lambda, n);
    evals.erase(evals.begin());
    int count = 1;
    while (count + static_cast<int>(lambda) <= budget_) {
      const std::vector<std::vector<double>> asked = Probe(cma, pop);
      if (asked.empty()) break;  // the step fell under xtol
      if (count == 1 && !first.empty() && asked != first) {
        throw std::logic_error("cmaes's first generation depends on the start point's cost");
      }
      if (count > 1 || first.empty()) {
        xs.clear();
        for (const auto& u : asked) xs.push_back(ToX(u));
        evals = rounds_.Submit(start_, xs);
      }
      Oracle& o = *oracle_;
      o.answers.clear();
      for (const Evaluation& e : evals) o.answers.push_back(e.objective);
      o.recording = false;
      o.next = 0;
      pop = cma.evolve(pop);
      count += static_cast<int>(lambda);
    }
  }

 private:
  // λ copies of the start point with cost f: the first mean is the population's best.
  pagmo::population Population(const std::vector<double>& u0, double f, unsigned lambda,
                               unsigned n) const {
    pagmo::population pop(pagmo::problem(CmaesProblem{oracle_, n}), 0u, seed_);
    for (unsigned i = 0; i < lambda; ++i) pop.push_back(u0, {f});
    return pop;
  }

  // The points the next generation asks for: a copy of the algorithm evolves against the
  // recording problem.
  std::vector<std::vector<double>> Probe(const pagmo::cmaes& cma, pagmo::population pop) const {
    oracle_->recording = true;
    oracle_->asked.clear();
    const pagmo::cmaes probe = cma;
    probe.evolve(pop);
    return oracle_->asked;
  }

  std::vector<double> ToX(const std::vector<double>& u) const {
    std::vector<double> x(u.size());
    for (size_t i = 0; i < u.size(); ++i) {
      x[i] = lo_[i] + std::clamp(u[i], 0.0, 1.0) * (hi_[i] - lo_[i]);
    }
    return x;
  }

  const Problem& problem_;
  const int start_;
  const int budget_;
  Evaluator& rounds_;
  const std::vector<double> lo_, hi_;
  std::shared_ptr<Oracle> oracle_;
  unsigned seed_ = 0;
};

}  // namespace

std::exception_ptr DriveStarts(const Problem& problem, const std::vector<int>& budget,
                               Shared& shared, int threads, Comm& comm,
                               std::vector<std::string>* errors) {
  const int starts = static_cast<int>(budget.size());
  Evaluator evaluator(problem, shared, threads, comm);
  common::ParallelFor(starts + 1, starts + 1, [&](int s) {
    if (s == starts) return evaluator.Serve();
    try {
      if (problem.params().algorithm == "cmaes") {
        CmaesStart(problem, s, budget[s], evaluator).Run();
      } else {
        StartRunner(problem, s, budget[s], evaluator).Run();
      }
    } catch (const std::exception& e) {
      (*errors)[s] = e.what();
    }
    evaluator.Finish(s);
  });
  return evaluator.stop_error();
}

}  // namespace climbsim::optimise::internal
