// Internal to climbsim::cpg: include "cpg/cpg.h", not this file.
//
// One place that owns the Boost.Odeint steppers and the state buffer of a network, so that
// both oscillator networks integrate the same way and neither allocates in its step:
//   * the state is a std::vector<double> sized once, in the constructor;
//   * every stepper's scratch buffers are sized in the constructor too (adjust_size), so odeint's
//     "initially_resizer" finds them the right size on the first step and never resizes;
//   * the steppers are members, so the controlled Dopri5 keeps its step size and its FSAL
//     derivative from one Step to the next.
#ifndef CLIMBSIM_CPG_INTERNAL_ODEINT_DRIVER_H_
#define CLIMBSIM_CPG_INTERNAL_ODEINT_DRIVER_H_

#include <algorithm>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/controlled_step_result.hpp>
#include <boost/numeric/odeint/stepper/euler.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace climbsim::cpg {

struct StepperParams;  // oscillator_network.h

namespace internal {

class OdeintDriver {
 public:
  using State = std::vector<double>;

  // Sizes the state (zeros) and every stepper's scratch. params must be valid (cpg.h checks).
  OdeintDriver(const StepperParams& params, std::size_t state_size);

  State& x() { return x_; }
  const State& x() const { return x_; }

  // Advances x() by dt_s > 0 with derivative(x, dxdt) (raw arrays of the state's size; a
  // lambda calling a network's private Derivative). Euler and RK4 take one step of dt_s (the
  // caller's dt sets their accuracy); Dopri5 takes as many accepted steps as its tolerances need,
  // the last one cut to land on dt_s, and remembers the step size for the next call. Returns
  // false if Dopri5 rejected kMaxConsecutiveRejections steps in a row: x() then holds the last
  // accepted state, short of dt_s by the returned remainder in *unfinished_s.
  template <class Derivative>
  bool Advance(Derivative derivative, double dt_s, double* unfinished_s);

  // Call after the right-hand side changed between calls (new feedback) or x() was rewritten:
  // Dopri5 reuses the derivative at the end of the previous step (first same as last), which is
  // then stale. Keeps the step-size hint. Never allocates.
  void InvalidateDerivative() { dopri5_.reset(); }
  // As above, and forgets the step-size hint and the counters (after a Reset of the network).
  void Restart();

  std::int64_t accepted_steps() const { return accepted_steps_; }
  std::int64_t rejected_steps() const { return rejected_steps_; }

  // A Dopri5 step rejected this many times in a row means the step size has collapsed (NaN
  // state or a discontinuous right-hand side); give up rather than spin.
  static constexpr int kMaxConsecutiveRejections = 60;

 private:
  enum class Method { kEuler, kRk4, kDopri5 };
  using Euler = boost::numeric::odeint::euler<State>;
  using Rk4 = boost::numeric::odeint::runge_kutta4<State>;
  using Dopri5 = boost::numeric::odeint::controlled_runge_kutta<
      boost::numeric::odeint::runge_kutta_dopri5<State>>;

  Method method_;
  State x_;
  Euler euler_;
  Rk4 rk4_;
  Dopri5 dopri5_;
  double dt_hint_s_ = 0.0;  // 0: no accepted step yet, try dt_s first
  std::int64_t accepted_steps_ = 0;
  std::int64_t rejected_steps_ = 0;
};

template <class Derivative>
bool OdeintDriver::Advance(Derivative derivative, double dt_s, double* unfinished_s) {
  // The system odeint calls; it captures by reference, so odeint's copies of it cost nothing.
  auto system = [&derivative](const State& x, State& dxdt, double) {
    derivative(x.data(), dxdt.data());
  };
  *unfinished_s = 0.0;
  if (method_ == Method::kEuler) {
    euler_.do_step(system, x_, 0.0, dt_s);
    ++accepted_steps_;
    return true;
  }
  if (method_ == Method::kRk4) {
    rk4_.do_step(system, x_, 0.0, dt_s);
    ++accepted_steps_;
    return true;
  }
  // Ends within this share of dt_s count as arrived: t + (dt_s - t) need not round to dt_s.
  constexpr double kArrivedFraction = 1e-12;
  double t_s = 0.0;
  int consecutive_rejections = 0;
  while (dt_s - t_s > kArrivedFraction * dt_s) {
    const double remaining_s = dt_s - t_s;
    const bool cut = dt_hint_s_ <= 0.0 || dt_hint_s_ >= remaining_s;
    double h_s = cut ? remaining_s : dt_hint_s_;
    if (dopri5_.try_step(system, x_, t_s, h_s) == boost::numeric::odeint::success) {
      ++accepted_steps_;
      consecutive_rejections = 0;
      // A step cut short to land on dt_s says little about the step the solution allows; keep
      // the hint unless it was never set.
      if (!cut || dt_hint_s_ <= 0.0) dt_hint_s_ = h_s;
    } else {
      ++rejected_steps_;
      dt_hint_s_ = h_s;  // the controller's smaller step
      if (++consecutive_rejections >= kMaxConsecutiveRejections) {
        *unfinished_s = dt_s - t_s;
        return false;
      }
    }
  }
  return true;
}

}  // namespace internal
}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_INTERNAL_ODEINT_DRIVER_H_
