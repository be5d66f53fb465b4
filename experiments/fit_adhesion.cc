// The fit of climbsim fit-adhesion (fit_adhesion.h): each law's parameters, the predictions
// through adhesion/pulloff.h's search on the bond grid, NLopt, and the uncertainties.
#include "experiments/fit_adhesion.h"

#include <nlopt.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include "common/common.h"

namespace climbsim::optimise {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// The pull-off search's cap (σ_T·A multiples): a pad that holds beyond it predicts the cap.
constexpr double kMaxForceFactor = 20.0;

struct Spec {
  std::string key, unit;
  double lo = 0.0, hi = 0.0;
  bool scale = false;  // a strength: every prediction is proportional to it
  double start = 0.0;
};

struct Model {
  std::string law;
  std::vector<Spec> specs;
  std::vector<std::pair<double, double>> nodes;  // tabulated: (angle, azimuth) per parameter
};

bool AnyPush(const PulloffData& d) {
  for (const auto& r : d.rows) {
    if (r.angle_from_normal_deg > 90.0) return true;
  }
  return false;
}

double MeanTraction(const PulloffData& d) {
  double sum = 0.0;
  for (const auto& r : d.rows) sum += r.force_n / (r.width_m * r.length_m);
  return std::max(sum / d.rows.size(), 1.0);
}

// Tabulated: one node per distinct (angle, azimuth); the start is the mean measured force
// there, scaled to the first row's pad.
void TabulatedSpecs(const PulloffData& d, Model* m) {
  const double area = d.rows[0].width_m * d.rows[0].length_m;
  std::map<std::pair<double, double>, std::pair<double, int>> sums;
  double largest = 0.0;
  for (const auto& r : d.rows) {
    if (r.angle_from_normal_deg > 90.0) {
      throw InputError(d.file, r.line, 1, "angle_from_normal_deg",
                       "law tabulated takes pulls only (angles 0 to 90), got " +
                           ShortNumber(r.angle_from_normal_deg));
    }
    // A straight pull has no azimuth: one node.
    const bool azimuth = d.has_azimuth && r.angle_from_normal_deg > 0.0;
    auto& s = sums[{r.angle_from_normal_deg, azimuth ? r.azimuth_deg : 0.0}];
    s.first += r.force_n * area / (r.width_m * r.length_m);
    ++s.second;
    largest = std::max(largest, r.force_n * area / (r.width_m * r.length_m));
  }
  for (const auto& [node, s] : sums) {
    m->nodes.push_back(node);
    m->specs.push_back({"tabulated.pulloff_n", "N", 0.0, 10.0 * std::max(largest, 1e-3), true,
                        s.first / s.second});
  }
}

Model MakeModel(const PulloffData& d, const FitAdhesionOptions& o) {
  Model m;
  m.law = o.law;
  const double traction = MeanTraction(d);
  if (o.law == "von_mises") {
    m.specs.push_back({"sigma_t_pa", "Pa", 1e-3, 1e12, true, traction});
    if (AnyPush(d)) m.specs.push_back({"mu", "", 0.0, 10.0, false, 0.5});
  } else if (o.law == "frictional") {
    m.specs.push_back({"frictional.shear_limit_pa", "Pa", 1e-3, 1e12, true, traction});
    m.specs.push_back({"frictional.critical_angle_deg", "deg", 0.5, 89.5, false, 30.0});
    if (AnyPush(d)) m.specs.push_back({"frictional.friction_mu", "", 0.0, 10.0, false, 1.0});
  } else if (o.law == "tabulated") {
    TabulatedSpecs(d, &m);
  } else {
    throw InputError("fit-adhesion", 0, 0, "--law",
                     "must be von_mises, frictional or tabulated, got " + o.law);
  }
  return m;
}

// The laws' parameter structs from x (the fit's current point).
void Apply(const Model& m, const std::vector<double>& x, const PulloffData& d,
           const FitAdhesionOptions& o, AdhesionFit* fit) {
  fit->law = m.law;
  fit->von_mises = adhesion::PadParams{};
  fit->frictional = adhesion::FrictionalParams{};
  fit->frictional.grip_x = std::cos(o.grip_deg * kDeg);
  fit->frictional.grip_y = std::sin(o.grip_deg * kDeg);
  adhesion::TabulatedParams& t = fit->tabulated;
  t = adhesion::TabulatedParams{};
  t.width_m = d.rows[0].width_m;
  t.length_m = d.rows[0].length_m;
  for (size_t i = 0; i < m.specs.size(); ++i) {
    const std::string& k = m.specs[i].key;
    if (k == "sigma_t_pa") fit->von_mises.sigma_t_pa = x[i];
    if (k == "mu") fit->von_mises.mu = x[i];
    if (k == "frictional.shear_limit_pa") fit->frictional.shear_limit_pa = x[i];
    if (k == "frictional.critical_angle_deg") fit->frictional.critical_angle_deg = x[i];
    if (k == "frictional.friction_mu") fit->frictional.friction_mu = x[i];
    if (k == "tabulated.pulloff_n") {
      t.angle_from_normal_deg.push_back(m.nodes[i].first);
      if (d.has_azimuth) t.azimuth_deg.push_back(m.nodes[i].second);
      t.pulloff_n.push_back(x[i]);
    }
  }
}

std::vector<double> PredictAll(const AdhesionFit& fit, const PulloffData& d, int grid) {
  std::vector<double> p(d.rows.size());
  for (size_t k = 0; k < d.rows.size(); ++k) p[k] = PredictPulloff(fit, d.rows[k], grid);
  return p;
}

double Sse(const std::vector<double>& p, const PulloffData& d) {
  double sse = 0.0;
  for (size_t k = 0; k < p.size(); ++k) sse += (p[k] - d.rows[k].force_n) * (p[k] - d.rows[k].force_n);
  return sse;
}

// The fit's state across NLopt's callbacks.
class Fitter {
 public:
  Fitter(const Model& m, const PulloffData& d, const FitAdhesionOptions& o)
      : m_(m), d_(d), o_(o), best_x_(StartPoint()) {}

  std::vector<double> Run();
  int evaluations() const { return evaluations_; }

  // SSE at x (every parameter), counting it.
  double Evaluate(const std::vector<double>& x, std::vector<double>* predicted = nullptr) {
    AdhesionFit fit;
    Apply(m_, x, d_, o_, &fit);
    std::vector<double> p = PredictAll(fit, d_, o_.grid);
    ++evaluations_;
    const double sse = Sse(p, d_);
    if (sse < best_sse_) {
      best_sse_ = sse;
      best_x_ = x;
    }
    if (o_.progress && evaluations_ % 200 == 0) {
      std::ostringstream s;
      s << "fit-adhesion: " << m_.law << ": " << evaluations_ << " evaluations, RMS "
        << std::sqrt(best_sse_ / d_.rows.size()) << " N";
      o_.progress(s.str());
    }
    if (predicted) *predicted = std::move(p);
    return sse;
  }

 private:
  std::vector<double> StartPoint() const {
    std::vector<double> x;
    for (const Spec& s : m_.specs) x.push_back(s.start);
    return x;
  }
  void Global();
  void Local();

  const Model& m_;
  const PulloffData& d_;
  const FitAdhesionOptions& o_;
  std::vector<double> best_x_;
  double best_sse_ = std::numeric_limits<double>::infinity();
  int evaluations_ = 0;
};

// Stage 1: DIRECT-L over the parameters that are not scales (unit box), each point's scale
// by least squares in closed form (predictions are proportional to it).
void Fitter::Global() {
  std::vector<int> free;
  for (size_t i = 0; i < m_.specs.size(); ++i) {
    if (!m_.specs[i].scale) free.push_back(static_cast<int>(i));
  }
  if (free.empty()) return;
  struct Ctx {
    Fitter* f;
    std::vector<int> free;
  } ctx{this, free};
  const auto objective = [](const std::vector<double>& u, std::vector<double>&, void* data) {
    Ctx* c = static_cast<Ctx*>(data);
    std::vector<double> x = c->f->best_x_;
    for (size_t j = 0; j < c->free.size(); ++j) {
      const Spec& s = c->f->m_.specs[c->free[j]];
      x[c->free[j]] = s.lo + std::clamp(u[j], 0.0, 1.0) * (s.hi - s.lo);
    }
    std::vector<double> p;
    c->f->Evaluate(x, &p);
    double py = 0.0, pp = 0.0;
    for (size_t k = 0; k < p.size(); ++k) {
      py += p[k] * c->f->d_.rows[k].force_n;
      pp += p[k] * p[k];
    }
    if (!(pp > 0.0) || !(py > 0.0)) return c->f->Evaluate(x);
    for (size_t i = 0; i < x.size(); ++i) {
      if (c->f->m_.specs[i].scale) x[i] *= py / pp;
    }
    return c->f->Evaluate(x);
  };
  nlopt::opt opt(nlopt::GN_DIRECT_L, static_cast<unsigned>(free.size()));
  opt.set_lower_bounds(std::vector<double>(free.size(), 0.0));
  opt.set_upper_bounds(std::vector<double>(free.size(), 1.0));
  opt.set_min_objective(objective, &ctx);
  // Two table predictions per point; DIRECT-L divides the box by thirds, so 60 points per
  // dimension resolve it to about 1/3^4 of each range before the local stage.
  opt.set_maxeval(std::min(o_.max_evaluations / 2, 60 * static_cast<int>(free.size())));
  std::vector<double> u(free.size(), 0.5);
  double f = 0.0;
  try {
    opt.optimize(u, f);
  } catch (const std::exception&) {
    // NLopt's round-off and stop conditions end the stage; the best point is kept.
  }
}

// Stage 2: BOBYQA over every parameter, each as a share of its own start (or range).
void Fitter::Local() {
  const size_t n = m_.specs.size();
  std::vector<double> typical(n), lo(n), hi(n), u(n);
  for (size_t i = 0; i < n; ++i) {
    const Spec& s = m_.specs[i];
    typical[i] = s.scale ? std::max(std::abs(best_x_[i]), 1e-6 * (s.hi - s.lo) + 1e-9)
                         : (s.hi - s.lo);
    lo[i] = s.lo / typical[i];
    hi[i] = s.hi / typical[i];
    u[i] = best_x_[i] / typical[i];
  }
  struct Ctx {
    Fitter* f;
    std::vector<double> typical;
  } ctx{this, typical};
  const auto objective = [](const std::vector<double>& v, std::vector<double>&, void* data) {
    Ctx* c = static_cast<Ctx*>(data);
    std::vector<double> x(v.size());
    for (size_t i = 0; i < v.size(); ++i) x[i] = v[i] * c->typical[i];
    return c->f->Evaluate(x);
  };
  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_min_objective(objective, &ctx);
  opt.set_maxeval(o_.max_evaluations);
  opt.set_xtol_rel(1e-7);
  std::vector<double> step(n);
  for (size_t i = 0; i < n; ++i) step[i] = std::min(0.05, 0.25 * (hi[i] - lo[i]));
  opt.set_initial_step(step);
  double f = 0.0;
  try {
    opt.optimize(u, f);
  } catch (const std::exception&) {
    // As above.
  }
}

std::vector<double> Fitter::Run() {
  Evaluate(best_x_);
  Global();
  Local();
  return best_x_;
}

// Measurement spread: the pooled standard deviation of repeats of one condition (angle,
// azimuth, pad, lever), or NaN without two rows of one condition.
double RepeatSpread(const PulloffData& d) {
  std::map<std::vector<double>, std::vector<double>> groups;
  for (const auto& r : d.rows) {
    groups[{r.angle_from_normal_deg, r.azimuth_deg, r.width_m, r.length_m, r.arm_m}].push_back(
        r.force_n);
  }
  double ss = 0.0;
  int dof = 0;
  for (const auto& [key, ys] : groups) {
    if (ys.size() < 2) continue;
    double mean = 0.0;
    for (double y : ys) mean += y / ys.size();
    for (double y : ys) ss += (y - mean) * (y - mean);
    dof += static_cast<int>(ys.size()) - 1;
  }
  return dof > 0 ? std::sqrt(ss / dof) : std::numeric_limits<double>::quiet_NaN();
}

bool SamePredictions(const std::vector<double>& a, const std::vector<double>& b, double tol) {
  for (size_t k = 0; k < a.size(); ++k) {
    if (std::abs(a[k] - b[k]) > tol) return false;
  }
  return true;
}

// A parameter the predictions do not change with near its value (a threshold, such as the
// frictional α*): the interval over which they stay the same, found by doubling and bisection.
void FlatInterval(Fitter* f, const std::vector<double>& x, size_t i, const Spec& s,
                  const std::vector<double>& p0, double tol, FittedParameter* out) {
  double edge[2];
  for (int side = 0; side < 2; ++side) {
    const double bound = side ? s.hi : s.lo;
    double inside = x[i], outside = bound;
    for (double step = 1e-3 * (s.hi - s.lo); std::abs(step) < (s.hi - s.lo); step *= 2.0) {
      const double t = std::clamp(x[i] + (side ? step : -step), s.lo, s.hi);
      std::vector<double> y = x, p;
      y[i] = t;
      f->Evaluate(y, &p);
      if (!SamePredictions(p, p0, tol)) {
        outside = t;
        break;
      }
      inside = t;
      if (t == bound) break;
    }
    for (int k = 0; k < 30 && outside != inside; ++k) {
      std::vector<double> y = x, p;
      y[i] = 0.5 * (inside + outside);
      f->Evaluate(y, &p);
      (SamePredictions(p, p0, tol) ? inside : outside) = y[i];
    }
    edge[side] = 0.5 * (inside + outside);
  }
  out->low95 = edge[0];
  out->high95 = edge[1];
  out->value = 0.5 * (edge[0] + edge[1]);
  out->uncertainty = (edge[1] - edge[0]) / (2.0 * std::sqrt(3.0));  // uniform over it
}

// Uncertainties: the smooth parameters from the fit's curvature (σ²·(JᵀJ)⁻¹, σ the repeats'
// spread or the residuals'), the flat ones as the interval they can move in.
void Uncertainties(Fitter* f, const Model& m, const PulloffData& d, double sigma,
                   std::vector<double>* x, AdhesionFit* fit) {
  const size_t n = m.specs.size(), rows = d.rows.size();
  std::vector<double> p0;
  f->Evaluate(*x, &p0);
  double ymax = 0.0;
  for (const auto& r : d.rows) ymax = std::max(ymax, r.force_n);
  const double tol = 1e-7 * std::max(ymax, 1e-9);
  Eigen::MatrixXd jac(rows, n);
  std::vector<bool> flat(n, false);
  for (size_t i = 0; i < n; ++i) {
    const Spec& s = m.specs[i];
    const double h = 1e-4 * (s.scale ? std::max(std::abs((*x)[i]), 1e-9) : (s.hi - s.lo));
    std::vector<double> up = *x, down = *x, pu, pd;
    up[i] = std::min((*x)[i] + h, s.hi);
    down[i] = std::max((*x)[i] - h, s.lo);
    f->Evaluate(up, &pu);
    f->Evaluate(down, &pd);
    for (size_t k = 0; k < rows; ++k) jac(k, i) = (pu[k] - pd[k]) / (up[i] - down[i]);
    flat[i] = SamePredictions(pu, p0, tol) && SamePredictions(pd, p0, tol);
    fit->parameters.push_back({s.key, s.unit, (*x)[i], 0, 0, 0, true});
  }
  std::vector<int> smooth;
  for (size_t i = 0; i < n; ++i) {
    if (!flat[i]) smooth.push_back(static_cast<int>(i));
  }
  Eigen::MatrixXd js(rows, smooth.size());
  for (size_t j = 0; j < smooth.size(); ++j) js.col(j) = jac.col(smooth[j]);
  const Eigen::MatrixXd cov =
      (js.transpose() * js).completeOrthogonalDecomposition().pseudoInverse();
  for (size_t j = 0; j < smooth.size(); ++j) {
    FittedParameter& q = fit->parameters[smooth[j]];
    q.uncertainty = sigma * std::sqrt(std::max(cov(j, j), 0.0));
    q.low95 = q.value - 1.96 * q.uncertainty;
    q.high95 = q.value + 1.96 * q.uncertainty;
  }
  for (size_t i = 0; i < n; ++i) {
    if (flat[i]) FlatInterval(f, *x, i, m.specs[i], p0, tol, &fit->parameters[i]);
    (*x)[i] = fit->parameters[i].value;
  }
}

void Verdict(const PulloffData& d, const FitAdhesionOptions& o, AdhesionFit* fit) {
  const size_t rows = d.rows.size();
  const double repeats = RepeatSpread(d);
  fit->spread_from_repeats = std::isfinite(repeats);
  double sse = 0.0, yy = 0.0, zz = 0.0, worst_z = 0.0;
  for (size_t k = 0; k < rows; ++k) yy += d.rows[k].force_n * d.rows[k].force_n;
  fit->spread_n = fit->spread_from_repeats ? repeats : o.assumed_spread * std::sqrt(yy / rows);
  for (size_t k = 0; k < rows; ++k) {
    const double y = d.rows[k].force_n, p = fit->predicted_n[k], r = y - p;
    // Without repeats each force is taken as known to assumed_spread of itself (of the
    // prediction where larger: a measured 0 is no better known than the force it misses).
    const double spread = fit->spread_from_repeats
                              ? repeats
                              : o.assumed_spread * std::max({y, p, 1e-3 * fit->spread_n});
    const double z = r / spread;
    sse += r * r;
    zz += z * z;
    if (std::abs(z) > worst_z) {
      worst_z = std::abs(z);
      fit->worst_n = std::abs(r);
      fit->worst_row = static_cast<int>(k);
    }
  }
  fit->rms_n = std::sqrt(sse / rows);
  // Residuals of a law that fits scatter like the measurements: their RMS about one spread,
  // the worst within four (rarely exceeded by 50 normal residuals).
  fit->represents = std::sqrt(zz / rows) <= 2.0 && worst_z <= 4.0;
  const PulloffMeasurement& w = d.rows[fit->worst_row];
  std::ostringstream s;
  s.precision(3);
  s << fit->law << ": RMS residual " << fit->rms_n << " N, " << std::sqrt(zz / rows)
    << " spreads; worst " << fit->worst_n << " N, " << worst_z << " spreads (line " << w.line
    << ", " << w.angle_from_normal_deg << " deg from the normal); measurement spread "
    << (fit->spread_from_repeats
            ? ShortNumber(repeats) + " N from the repeats"
            : "assumed " + ShortNumber(100 * o.assumed_spread) + " % of each force (no repeats)")
    << ": "
    << (fit->represents ? "the law represents your data"
                        : "this law cannot represent your data");
  fit->verdict = s.str();
}

}  // namespace

void CheckFitData(const PulloffData& data, const std::string& law) {
  FitAdhesionOptions options;
  options.law = law;
  MakeModel(data, options);
}

double PredictPulloff(const AdhesionFit& fit, const PulloffMeasurement& row, int grid) {
  adhesion::PadParams pad = fit.von_mises;
  pad.width_m = row.width_m;
  pad.length_m = row.length_m;
  pad.grid_x = pad.grid_y = grid;
  const adhesion::PullSetup setup{.angle_rad = row.angle_from_normal_deg * kDeg,
                                  .azimuth_rad = row.azimuth_deg * kDeg,
                                  .arm_m = row.arm_m};
  adhesion::PulloffOptions options;
  options.max_force_factor = kMaxForceFactor;
  adhesion::PulloffResult r;
  if (fit.law == "von_mises") {
    r = adhesion::PullOff(pad, setup, options);
  } else if (fit.law == "frictional") {
    r = adhesion::FrictionalPullOff(pad, fit.frictional, setup, options);
  } else {
    r = adhesion::TabulatedPullOff(pad, fit.tabulated, setup, options);
  }
  return r.detaches ? r.force_n : r.holding_force_n;
}

AdhesionFit FitAdhesion(const PulloffData& data, const FitAdhesionOptions& options) {
  const Model model = MakeModel(data, options);
  Fitter fitter(model, data, options);
  std::vector<double> x = fitter.Run();
  AdhesionFit fit;
  Apply(model, x, data, options, &fit);
  fit.predicted_n = PredictAll(fit, data, options.grid);
  // σ for the curvature: the repeats' spread, else the residuals' (with n − p degrees).
  // Rows measured and predicted 0 (a directional pad pulled too steeply) carry no scatter.
  size_t n = 0;
  for (size_t k = 0; k < data.rows.size(); ++k) {
    n += data.rows[k].force_n > 0.0 || fit.predicted_n[k] > 0.0 ? 1 : 0;
  }
  const size_t p = model.specs.size();
  double sigma = RepeatSpread(data);
  if (!std::isfinite(sigma)) {
    sigma = n > p ? std::sqrt(Sse(fit.predicted_n, data) / (n - p))
                  : std::numeric_limits<double>::quiet_NaN();
  }
  Uncertainties(&fitter, model, data, sigma, &x, &fit);
  Apply(model, x, data, options, &fit);  // flat parameters moved to their intervals' middle
  fit.predicted_n = PredictAll(fit, data, options.grid);
  fit.evaluations = fitter.evaluations();
  Verdict(data, options, &fit);
  return fit;
}

}  // namespace climbsim::optimise
