// The interface both oscillator networks share (cpg/cpg.h has the phase convention), and how
// they integrate: the Odeint stepper, its status and counters.
#ifndef CLIMBSIM_CPG_OSCILLATOR_NETWORK_H_
#define CLIMBSIM_CPG_OSCILLATOR_NETWORK_H_

#include <cstdint>
#include <optional>
#include <span>

namespace climbsim::cpg {

// ---------------------------------------------------------------------------------------------
// Integration
// ---------------------------------------------------------------------------------------------

// Odeint stepper used by a network's Step(dt_s).
//   kEuler   explicit Euler, one step of dt_s: first order, global error ∝ dt.
//   kRk4     classic Runge–Kutta, one step of dt_s: fourth order, global error ∝ dt⁴.
//   kDopri5  Dormand–Prince 5(4) under odeint's step-size controller: as many internal steps
//            as the tolerances need per Step, the step size carried over between Steps.
enum class Stepper { kEuler, kRk4, kDopri5 };

// abs_tol, rel_tol: Dopri5's local error bound per internal step and per state component i,
//   |err_i| ≤ abs_tol + rel_tol·(|x_i| + h·|dx_i/dt|)   (odeint's default_error_checker).
// State components are phases in rad (kept in [0, 2π)) and amplitudes (~1), so both
// tolerances are, in practice, in rad. Euler and RK4 ignore them, but they are still checked.
// Throws std::invalid_argument (at network construction): a tolerance negative or not
// finite, both zero, or type not one of the enumerators.
struct StepperParams {
  Stepper type = Stepper::kRk4;
  double abs_tol = 1e-8;
  double rel_tol = 1e-6;
};

// What the last Step reports; the state keeps the last good values it could compute.
enum class StepStatus {
  kOk,
  kStepSizeUnderflow,  // Dopri5 rejected OdeintDriver::kMaxConsecutiveRejections steps in a row
  kNonFinite,          // a phase or an amplitude became NaN/inf (non-finite feedback, say)
};

// Counters since construction or the last Reset, for benchmarks and diagnostics.
struct IntegrationStats {
  std::int64_t steps = 0;            // calls of Step
  std::int64_t accepted_steps = 0;   // odeint steps taken (Euler/RK4: == steps)
  std::int64_t rejected_steps = 0;   // Dopri5 only
  std::int64_t rhs_evaluations = 0;  // right-hand side calls: the cost
};

// ---------------------------------------------------------------------------------------------
// Common interface: the simulator composes either network through it.
// ---------------------------------------------------------------------------------------------

class OscillatorNetwork {
 public:
  virtual ~OscillatorNetwork() = default;

  virtual int size() const = 0;

  // Advances by dt_s ≥ 0 (0 does nothing). feedback_rad_per_s: empty, or one value per
  // oscillator, added to that oscillator's phase rate dθ_i/dt and held constant over the step
  // (e.g. TegotaeFeedback). Never allocates, not even on the first call. Throws
  // std::invalid_argument only for a caller's mistake: dt_s negative or NaN, or a feedback
  // span of the wrong size. Numerical trouble goes to status().
  virtual void Step(double dt_s, std::span<const double> feedback_rad_per_s,
                    std::span<const uint8_t> held) = 0;
  // held: empty, or one flag per oscillator; a held oscillator's state does not change over
  // the step (its derivative is zero: phase, amplitude, coupling and all), while the others
  // go on and still feel it through the coupling. A climber holds its welded stance legs
  // this way while a leg waits. Same contract otherwise.
  void Step(double dt_s, std::span<const double> feedback_rad_per_s) {
    Step(dt_s, feedback_rad_per_s, {});
  }

  // θ_i in [0, 2π), in the convention at the top of cpg/cpg.h.
  virtual std::span<const double> phase_rad() const = 0;
  // θ_i without wrapping: 2π per cycle completed since the last Reset (count steps with it).
  // Exact increments for PhaseNetwork; HopfNetwork adds the wrapped change of θ_i over each
  // Step, which assumes |Δθ_i| < π per Step (dt_s below half a period).
  virtual std::span<const double> phase_unwrapped_rad() const = 0;
  // Scales the leg shape: 1 = the nominal stride (see ShapeLeg).
  virtual std::span<const double> amplitude() const = 0;
  virtual double time_s() const = 0;

  // The duty factor to pass to ShapeLeg. nullopt: the phase runs at a uniform rate, so the
  // gait's duty factor (in time) is the one to use. A value: the network puts stance and swing
  // at fixed phases itself and runs through them at different rates (HopfNetwork: ½).
  virtual std::optional<double> phase_duty_factor() const = 0;

  virtual StepStatus status() const = 0;
  virtual IntegrationStats stats() const = 0;

  // Moves every oscillator to phase θ_i (any real, wrapped), keeping its amplitude, time and
  // counters: a controller that had the legs hands them back at a gait moment of its choice.
  // The unwrapped phase starts again from θ_i. No checks (θ must be finite), no allocation.
  virtual void Rephase(std::span<const double> theta_rad) = 0;
};

}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_OSCILLATOR_NETWORK_H_
