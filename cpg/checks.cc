#include "cpg/internal/checks.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "cpg/cpg.h"

namespace climbsim::cpg::internal {

double WrapTwoPi(double theta_rad) {
  double wrapped = theta_rad - kTwoPi * std::floor(theta_rad / kTwoPi);
  if (wrapped >= kTwoPi || wrapped < 0.0) wrapped = 0.0;
  return wrapped;
}

StepStatus StepStatusOf(bool state_finite, bool step_finished) {
  return !state_finite    ? StepStatus::kNonFinite
         : !step_finished ? StepStatus::kStepSizeUnderflow
                          : StepStatus::kOk;
}

double WrapPi(double delta_rad) { return WrapTwoPi(delta_rad + kPi) - kPi; }

std::string Num(double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

void Fail(std::string_view field, std::string_view requirement, double got) {
  throw std::invalid_argument(std::string(field) + " must be " + std::string(requirement) +
                              ", got " + Num(got));
}

void Fail(std::string_view message) { throw std::invalid_argument(std::string(message)); }

void CheckFinite(std::string_view field, double value) {
  if (!std::isfinite(value)) Fail(field, "finite", value);
}

void CheckPositive(std::string_view field, double value) {
  if (!(std::isfinite(value) && value > 0.0)) Fail(field, "finite and > 0", value);
}

void CheckNonNegative(std::string_view field, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) Fail(field, "finite and >= 0", value);
}

void CheckSquare(std::string_view field, const Eigen::MatrixXd& m, int n, std::string_view why_n) {
  if (m.rows() != n || m.cols() != n) {
    Fail(std::string(field) + " must be " + std::to_string(n) + "x" + std::to_string(n) + " (" +
         std::string(why_n) + "), got " + std::to_string(m.rows()) + "x" +
         std::to_string(m.cols()));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (!std::isfinite(m(i, j))) {
        Fail(std::string(field) + "(" + std::to_string(i) + "," + std::to_string(j) + ")", "finite",
             m(i, j));
      }
    }
  }
}

void CheckZeroDiagonal(std::string_view field, const Eigen::MatrixXd& m) {
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    if (m(i, i) != 0.0) {
      Fail(std::string(field) + "(" + std::to_string(i) + "," + std::to_string(i) + ")",
           "0 (an oscillator is not coupled to itself)", m(i, i));
    }
  }
}

void CheckStepperParams(std::string_view owner, const StepperParams& params) {
  const std::string prefix = std::string(owner) + ".stepper.";
  if (params.type != Stepper::kEuler && params.type != Stepper::kRk4 &&
      params.type != Stepper::kDopri5) {
    Fail(prefix + "type", "kEuler, kRk4 or kDopri5", static_cast<double>(params.type));
  }
  CheckNonNegative(prefix + "abs_tol", params.abs_tol);
  CheckNonNegative(prefix + "rel_tol", params.rel_tol);
  if (params.abs_tol == 0.0 && params.rel_tol == 0.0) {
    Fail(prefix + "abs_tol and " + prefix +
         "rel_tol are both 0: Dopri5 could never meet them; give one of them > 0");
  }
}

bool StepInputs::Latch(std::string_view owner, double dt_s,
                       std::span<const double> feedback_rad_per_s, std::span<const uint8_t> held) {
  const int n = static_cast<int>(held_.size());
  // The owner's name is built on the error paths only: this runs every step.
  const auto who = [owner] { return std::string(owner); };
  if (!(dt_s >= 0.0)) Fail(who() + "::Step: dt_s", ">= 0", dt_s);
  if (!feedback_rad_per_s.empty() && static_cast<int>(feedback_rad_per_s.size()) != n) {
    Fail(who() + "::Step: feedback_rad_per_s must be empty or have " + std::to_string(n) +
         " entries, got " + std::to_string(feedback_rad_per_s.size()));
  }
  if (!held.empty() && static_cast<int>(held.size()) != n) {
    Fail(who() + "::Step: held must be empty or have " + std::to_string(n) + " entries, got " +
         std::to_string(held.size()));
  }
  bool changed = false;
  for (int i = 0; i < n; ++i) {
    const double f = feedback_rad_per_s.empty() ? 0.0 : feedback_rad_per_s[i];
    const uint8_t h = held.empty() ? 0 : held[i] != 0;
    changed |= f != feedback_rad_per_s_[i] || h != held_[i];
    feedback_rad_per_s_[i] = f;
    held_[i] = h;
  }
  return changed;
}

void StepInputs::Clear() {
  std::fill(feedback_rad_per_s_.begin(), feedback_rad_per_s_.end(), 0.0);
  std::fill(held_.begin(), held_.end(), 0);
}

}  // namespace climbsim::cpg::internal
