// climbsim::cpg — central pattern generators for legged climbers.
//
// One oscillator per leg, coupled so that the legs keep a gait's phase offsets; each
// oscillator's phase and amplitude are then shaped into three joint targets per leg. Two kinds
// of oscillator share one interface (OscillatorNetwork), both integrated with Boost.Odeint:
//
//   PhaseNetwork  phase oscillators with amplitude (Ijspeert et al. 2007, Science 315:1416):
//                   dθ_i/dt = 2πf + Σ_j w_ij·r_j·sin(θ_j − θ_i − φ_ij) + feedback_i
//                   dr_i/dt = a·(R_i − r_i)
//   HopfNetwork   Hopf oscillators whose frequency switches between stance and swing
//                 (Righetti and Ijspeert 2008, ICRA, doi 10.1109/ROBOT.2008.4543306), coupled
//                 through rotation matrices so that any phase offset can be asked for.
//
// Phase convention (Owaki et al. 2013, generalised to any duty factor D): θ ∈ [0, 2π);
// swing for θ ∈ [0, 2π(1−D)), stance for θ ∈ [2π(1−D), 2π). A network's phase_rad() follows it.
//
// Gaits are phase offsets: leg i lags by offset_i cycles, θ_i = 2πft − 2π·offset_i in steady
// state (HopfNetwork: in its phase that is uniform in time), which the coupling enforces
// through φ_ij = 2π·(offset_i − offset_j).
//
// Nothing here knows of MuJoCo. Parameters are plain structs, checked once when a network is
// built (std::invalid_argument naming the field and the value); Step never throws on numbers
// and never allocates; trouble while integrating is reported by status(), not thrown.
// The README next to this file has the laws, the defaults, a snippet and the test map.
#ifndef CLIMBSIM_CPG_CPG_H_
#define CLIMBSIM_CPG_CPG_H_

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cpg/internal/checks.h"
#include "cpg/internal/odeint_driver.h"

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
// Gaits
// ---------------------------------------------------------------------------------------------

// offsets_cycles[i]: how far leg i lags, in cycles (legs start swing in order of increasing
// offset). duty_factor: share of the cycle in stance, in (0, 1).
struct Gait {
  std::vector<double> offsets_cycles;
  double duty_factor;
};

// Presets of docs/control.md's table, for the robots' leg orders:
//   4 legs (LF, RF, LH, RH):
//     "trot"              LF 0, RF ½, LH ½, RH 0                 D = ½
//     "lateral_sequence"  LF ¼, RF ¾, LH 0, RH ½               D = ¾  (LH, LF, RH, RF)
//   6 legs (L1, L2, L3, R1, R2, R3; 1 = front):
//     "tripod"            L1 0, L2 ½, L3 0, R1 ½, R2 0, R3 ½       D = ½
//     "tetrapod"          L1 ⅔, L2 ⅓, L3 0, R1 ⅓, R2 0, R3 ⅔       D = ⅔
//     "wave"              L1 ⅓, L2 ⅙, L3 0, R1 ⅚, R2 ⅔, R3 ½       D = ⅚
// Throws std::invalid_argument for an unknown name or a name not defined for num_legs (the
// message lists the names that are).
Gait GaitPreset(std::string_view name, int num_legs);

// Names GaitPreset accepts for num_legs; empty if there are none (num_legs other than 4, 6).
std::vector<std::string> GaitPresetNames(int num_legs);

// φ_ij = 2π·(offset_i − offset_j) rad, so that the locked network has θ_j − θ_i = φ_ij.
// Antisymmetric, zero diagonal. Throws std::invalid_argument for a non-finite offset.
Eigen::MatrixXd PhaseBiasFromOffsets(const std::vector<double>& offsets_cycles);

// weight_per_s on every off-diagonal entry, 0 on the diagonal. With equal weights the network
// locks to any bias that PhaseBiasFromOffsets produced from almost every start: substituting
// ϑ_i = θ_i + 2π·offset_i turns it into identical Kuramoto oscillators on a complete graph,
// which synchronise. Throws std::invalid_argument: num_oscillators < 1, weight not finite.
Eigen::MatrixXd AllToAllCoupling(int num_oscillators, double weight_per_s);

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

  // θ_i in [0, 2π), in the convention at the top of this file.
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

// ---------------------------------------------------------------------------------------------
// Phase oscillators (Ijspeert et al. 2007)
// ---------------------------------------------------------------------------------------------

// n oscillators, n = target_amplitude.size() ≥ 1.
//   frequency_hz          f > 0, common intrinsic frequency, Hz.               default 1
//   coupling_per_s        w_ij finite, n×n, zero diagonal, 1/s.                no default
//                         (w > 0 attracts to the bias; AllToAllCoupling builds one.)
//   phase_bias_rad        φ_ij, n×n, rad (PhaseBiasFromOffsets).               no default
//                         Its diagonal does not enter (w_ii = 0).
//   target_amplitude      R_i ≥ 0, dimensionless (1 = nominal stride).         no default
//   amplitude_rate_per_s  a ≥ 0, 1/s: r reaches R with time constant 1/a.      default 5
//   stepper               see StepperParams.
// Two oscillators with w_12 = w_21 = w and φ_21 = −φ_12 = −φ, at equal amplitude r, have
// ψ = θ_2 − θ_1 obeying dψ/dt = −2wr·sin(ψ − φ): tan((ψ−φ)/2) = tan((ψ0−φ)/2)·e^{−2wrt}.
// Throws std::invalid_argument (constructor) for a wrong size, a non-finite entry, f ≤ 0,
// R < 0, a < 0, a non-zero w_ii, or bad StepperParams; the message names the field.
struct PhaseNetworkParams {
  double frequency_hz = 1.0;
  Eigen::MatrixXd coupling_per_s;
  Eigen::MatrixXd phase_bias_rad;
  Eigen::VectorXd target_amplitude;
  double amplitude_rate_per_s = 5.0;  // the scenario key cpg.amplitude_rate_per_s
  StepperParams stepper;
};

// Equal coupling between all legs, the gait's bias, and amplitude R for every leg.
PhaseNetworkParams PhaseNetworkParamsForGait(const Gait& gait, double frequency_hz,
                                             double coupling_per_s, double amplitude = 1.0);

class PhaseNetwork final : public OscillatorNetwork {
 public:
  // Starts at t = 0 in the locked pattern, θ_i = φ_0i wrapped (leg 0 at θ = 0), with every
  // amplitude r_i = 0: the legs ease out of the neutral pose with time constant 1/a. Throws as
  // PhaseNetworkParams says.
  explicit PhaseNetwork(const PhaseNetworkParams& params);

  // Puts the network at θ (any real, wrapped into [0, 2π)) and r ≥ 0, t = 0, counters and
  // status cleared. Throws std::invalid_argument for a wrong size or a bad value.
  void Reset(const Eigen::VectorXd& theta_rad, const Eigen::VectorXd& amplitude);

  int size() const override { return n_; }
  using OscillatorNetwork::Step;
  void Step(double dt_s, std::span<const double> feedback_rad_per_s,
            std::span<const uint8_t> held) override;
  std::span<const double> phase_rad() const override;
  std::span<const double> phase_unwrapped_rad() const override { return unwrapped_rad_; }
  std::span<const double> amplitude() const override;
  double time_s() const override { return time_s_; }
  std::optional<double> phase_duty_factor() const override { return std::nullopt; }
  StepStatus status() const override { return status_; }
  IntegrationStats stats() const override;
  void Rephase(std::span<const double> theta_rad) override;

  const PhaseNetworkParams& params() const { return params_; }

 private:
  // dx/dt for x = [θ_0..θ_{n−1}, r_0..r_{n−1}], with the feedback held in feedback_.
  void Derivative(const double* x, double* dxdt);

  PhaseNetworkParams params_;
  int n_;
  // Params unpacked into flat row-major arrays, so that the right-hand side reads no Eigen
  // object; sin and cos of the biases are taken once, here, not in every evaluation.
  double omega_rad_per_s_;
  std::vector<double> weight_per_s_;
  std::vector<double> cos_bias_;
  std::vector<double> sin_bias_;
  // Scratch and state: all sized in the constructor.
  std::vector<double> sin_theta_;
  std::vector<double> cos_theta_;
  internal::StepInputs inputs_;
  std::vector<double> theta_before_rad_;
  std::vector<double> unwrapped_rad_;
  internal::OdeintDriver driver_;
  double time_s_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t rhs_evaluations_ = 0;
  StepStatus status_ = StepStatus::kOk;
};

// ---------------------------------------------------------------------------------------------
// Hopf oscillators with stance and swing frequencies (Righetti and Ijspeert 2008)
// ---------------------------------------------------------------------------------------------
//
//   dx_i/dt = α(μ − r_i²)·x_i − ω_i·y_i + Σ_j k_ij·(c_ij,x − x_i) − u_i·y_i
//   dy_i/dt = β(μ − r_i²)·y_i + ω_i·x_i + Σ_j k_ij·(c_ij,y − y_i) + u_i·x_i
//   ω_i = ω_stance/(e^{−b·y_i} + 1) + ω_swing/(e^{b·y_i} + 1),  r_i² = x_i² + y_i²,
//   ω_stance = 2π·stance_frequency_hz, ω_swing = 2π·swing_frequency_hz; u_i = feedback_i;
//   c_ij is where z_i = (x_i, y_i) would be if it kept its bias φ_ij to z_j (Coupling).
//
// Limit cycle: the circle r = sqrt(μ), run counter-clockwise at rate ω(y): ω_stance in the
// upper half (y > 0: stance, as in Righetti and Ijspeert), ω_swing in the lower half. b sets
// how sharply ω switches as y changes sign (over |y| ≲ 5/b).
//
// Phase. ϑ = atan2(y, x) runs swing over ϑ ∈ (−π, 0) and stance over (0, π); the convention
// of this file (swing first) is  θ = ϑ + π  wrapped to [0, 2π): swing θ ∈ [0, π), stance
// [π, 2π), swing starting at (x, y) = (−sqrt(μ), 0). Stance and swing are fixed halves of the
// phase, run at different speeds, so ShapeLeg must be called with duty factor ½
// (phase_duty_factor()). In time, with b → ∞ on the limit cycle,
//   T_stance = π/ω_stance,  T_swing = π/ω_swing,
//   D = T_stance/(T_stance + T_swing) = ω_swing/(ω_stance + ω_swing),
//   stride frequency 1/(T_stance + T_swing) = 2·f_stance·f_swing/(f_stance + f_swing);
// HopfFrequenciesForGait inverts this. (At b = 100 the blend of the two rates near y = 0
// shortens the period by ~0.3 % for D = ¾.) x runs +sqrt(μ) → −sqrt(μ) in stance and back in
// swing: it has the sign of ShapeLeg's stride.
//
// Coupling. Righetti and Ijspeert couple through Σ_j k_ij·y_j with ±1 entries per gait, which
// asks only for in-phase or anti-phase pairs. To ask for any φ_ij this file offers:
//   kRotation            c_ij = R(−φ_ij)·z_j, R the 2-D rotation: the rotation-matrix
//                        coupling of Hopf oscillators analysed by Chung and Slotine 2010
//                        (CDC, doi 10.1109/CDC.2010.5717962, "Hopf–Kuramoto" oscillators),
//                        in diffusive form (minus z_i, so it vanishes at the lock). On circles
//                        its tangential part adds k_ij·(r_j/r_i)·sin(ϑ_j − ϑ_i − φ_ij) to
//                        dϑ_i/dt, the phase network's term. It vanishes when the geometric
//                        angles differ by φ_ij, but with ω_stance ≠ ω_swing a locked gait keeps
//                        a time lag, not an angle: legs in different halves are then pulled
//                        all cycle long. The lag still locks (exactly, for the presets, whose
//                        symmetry makes the lagged solution exist), but the coupling speeds
//                        the network up and evens out stance and swing. Measured, all-to-all
//                        k = 2/s, 1 Hz: lateral_sequence period 0.89 s and stance share 0.66
//                        instead of 0.75; wave period 0.75 s. D = ½ gaits are unaffected.
//   kTimeWarpedRotation  (default) the same, but the rotation is done in the phase that is
//                        uniform in time, Φ = W(θ) (b → ∞, on the cycle: swing θ ∈ [0, π)
//                        maps linearly onto Φ ∈ [0, 2π(1−D)), stance onto [2π(1−D), 2π)):
//                        c_ij = r_j·(−cos θ*, −sin θ*), θ* = W⁻¹(W(θ_j) − φ_ij). It
//                        vanishes on the time-lagged gait itself, so a locked network keeps
//                        its own period, duty factor and radius whatever k. Measured up to
//                        k = 5/s: period within 3e-4 s, stance share within 2e-3, radius
//                        within 2e-4 of the uncoupled oscillator's (W ignores the blend at
//                        finite b, hence the residue).
//                        Near the lock its phase dynamics are the phase network's, in Φ:
//                        dΦ_i/dt ≈ Ω + Σ_j k_ij·(Φ_j − Φ_i − φ_ij). For D = ½, W is the
//                        identity and the two forms coincide. Costs n atan2 and 2n sin/cos
//                        per evaluation (the rotation by angle addition).
//
// Feedback. feedback_i (rad/s) enters as u_i on the tangent (−y_i, x_i), which adds exactly
// u_i to dϑ_i/dt at any radius and leaves the radius alone. Righetti and Ijspeert add their
// u_i to dy_i/dt only, which changes dϑ/dt by u_i·x_i/r_i², varying along the cycle; with the
// tangent form a Tegotae-style phase law means the same thing for both networks.
//
// Parameters (n = coupling_per_s.rows() ≥ 1):
//   stance_frequency_hz   f_stance > 0, Hz: ω_stance = 2π·f_stance.          default 1
//   swing_frequency_hz    f_swing > 0, Hz.                                   default 1
//   mu                    μ > 0, limit-cycle radius², (unit of x)².          default 1
//   alpha_per_s, beta_per_s  α, β > 0, 1/(s·μ): pull onto the circle; a radius error decays
//                         as e^{−2αμt} near y = 0 and e^{−2βμt} near x = 0.   default 50, 50
//   b                     > 0, 1/(unit of y): sharpness of the ω switch.     default 100
//   coupling_per_s        k_ij, n×n, zero diagonal, 1/s.                     no default
//   phase_bias_rad        φ_ij, n×n, rad (PhaseBiasFromOffsets): a lag in time, as
//                         fraction of the cycle × 2π (kRotation: a geometric angle).
//   coupling_form         HopfCoupling, see Coupling.                        kTimeWarpedRotation
//   stepper               see StepperParams. The ω switch is fast (y crosses |y| < 5/b in
//                         ~5/(b·ω·sqrt(μ)) s): give Euler/RK4 a dt_s well below that, or use
//                         Dopri5, which shortens its steps there.
// Throws std::invalid_argument (constructor) for a wrong size, a non-finite entry, a value out
// of the ranges above, a non-zero k_ii, or bad StepperParams; the message names the field.

// How a Hopf oscillator is pulled towards its phase bias: see Coupling above.
enum class HopfCoupling { kRotation, kTimeWarpedRotation };

struct HopfNetworkParams {
  double stance_frequency_hz = 1.0;
  double swing_frequency_hz = 1.0;
  double mu = 1.0;
  double alpha_per_s = 50.0;
  double beta_per_s = 50.0;
  double b = 100.0;
  Eigen::MatrixXd coupling_per_s;
  Eigen::MatrixXd phase_bias_rad;
  HopfCoupling coupling_form = HopfCoupling::kTimeWarpedRotation;
  StepperParams stepper;
};

struct HopfFrequencies {
  double stance_frequency_hz;
  double swing_frequency_hz;
};
// f_stance = f/(2D), f_swing = f/(2(1−D)): stance lasts D/f and swing (1−D)/f, in the b → ∞
// limit. Throws std::invalid_argument: f ≤ 0 or not finite, D outside (0, 1).
HopfFrequencies HopfFrequenciesForGait(double stride_frequency_hz, double duty_factor);

// Equal coupling between all legs, the gait's bias, and the two frequencies that give the
// gait's duty factor at stride_frequency_hz. Other fields at their defaults.
HopfNetworkParams HopfNetworkParamsForGait(const Gait& gait, double stride_frequency_hz,
                                           double coupling_per_s);

class HopfNetwork final : public OscillatorNetwork {
 public:
  // Starts at t = 0 on the limit cycle (r = sqrt(μ)) in the gait's pattern: leg 0 at θ = 0,
  // leg i lagging by φ_0i (kTimeWarpedRotation: in time, θ_i = W⁻¹(φ_0i); kRotation: in
  // angle, θ_i = φ_0i). Not at the origin: an unstable equilibrium it would never leave.
  explicit HopfNetwork(const HopfNetworkParams& params);

  // Places oscillator i at phase θ_i (this file's convention) and radius amplitude_i·sqrt(μ):
  // x = a·sqrt(μ)·cos(θ − π), y = a·sqrt(μ)·sin(θ − π). t = 0, counters and status cleared.
  // Throws std::invalid_argument for a wrong size, a non-finite value, or amplitude ≤ 0.
  void Reset(const Eigen::VectorXd& theta_rad, const Eigen::VectorXd& amplitude);

  int size() const override { return n_; }
  using OscillatorNetwork::Step;
  void Step(double dt_s, std::span<const double> feedback_rad_per_s,
            std::span<const uint8_t> held) override;
  std::span<const double> phase_rad() const override { return phase_rad_; }
  std::span<const double> phase_unwrapped_rad() const override { return unwrapped_rad_; }
  // r_i/sqrt(μ): 1 on the limit cycle.
  std::span<const double> amplitude() const override { return amplitude_; }
  double time_s() const override { return time_s_; }
  // ½: stance is always θ ∈ [π, 2π), whatever the frequencies.
  std::optional<double> phase_duty_factor() const override { return 0.5; }
  StepStatus status() const override { return status_; }
  IntegrationStats stats() const override;
  void Rephase(std::span<const double> theta_rad) override;

  // The Cartesian state, first n entries of the odeint state and the next n.
  std::span<const double> x() const;
  std::span<const double> y() const;
  // Duty factor in time, ω_swing/(ω_stance + ω_swing), and stride frequency
  // 2·f_stance·f_swing/(f_stance + f_swing) Hz, both in the b → ∞ limit on the limit cycle.
  double duty_factor() const;
  double stride_frequency_hz() const;

  const HopfNetworkParams& params() const { return params_; }

 private:
  // dz/dt for z = [x_0..x_{n−1}, y_0..y_{n−1}], with the feedback held in feedback_.
  void Derivative(const double* z, double* dzdt);
  double TimePhase(double theta_rad) const;
  // phase_rad_, amplitude_ from the state; adds the wrapped phase change to unwrapped_rad_
  // if accumulate.
  void UpdateOutputs(bool accumulate);

  HopfNetworkParams params_;
  int n_;
  double omega_stance_rad_per_s_;
  double omega_swing_rad_per_s_;
  double sqrt_mu_;
  std::vector<double> weight_per_s_;
  std::vector<double> cos_bias_;
  std::vector<double> sin_bias_;
  double swing_share_;  // 1 − D: share of the time spent in swing (b → ∞)
  // kTimeWarpedRotation by angle addition (hopf_network.cc): per pair, φ_ij wrapped to
  // [0, 2π) and cos/sin of four constant angles; per oscillator and evaluation, its time
  // phase, radius and cos/sin of its time phase scaled by each half's slope.
  std::vector<double> warp_bias_rad_;
  std::vector<double> warp_cos_;
  std::vector<double> warp_sin_;
  std::vector<double> time_phase_rad_;
  std::vector<double> radius_;
  std::vector<double> scaled_cos_;
  std::vector<double> scaled_sin_;
  internal::StepInputs inputs_;
  std::vector<double> phase_rad_;
  std::vector<double> amplitude_;
  std::vector<double> unwrapped_rad_;
  internal::OdeintDriver driver_;
  double time_s_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t rhs_evaluations_ = 0;
  StepStatus status_ = StepStatus::kOk;
};

// ---------------------------------------------------------------------------------------------
// Load feedback (Tegotae; Owaki et al. 2013, J R Soc Interface; Owaki and Ishiguro 2017,
// Sci Rep, doi 10.1038/s41598-017-00348-9)
// ---------------------------------------------------------------------------------------------

// −σ·N·cos θ, rad/s, to pass to Step as feedback_i. σ in rad/(N·s) (6 for Owaki's quadruped),
// N the leg's normal load in N (on a climber, the pad's normal or adhesive load), θ the leg's
// phase. Load draws the phase towards mid-stance, 3π/2 in Owaki's halves (swing [0, π),
// stance [π, 2π)): sped up before it, slowed after it, so a leg that carries load stays in
// stance and one that is unloaded swings on at its own rate. That is this file's convention
// at D = ½ (so always for HopfNetwork); for a PhaseNetwork at another duty factor, stance is
// centred on 2π(1 − D/2) and cos θ no longer points at its middle: shift θ accordingly.
double TegotaeFeedback(double sigma_rad_per_n_s, double normal_load_n, double theta_rad);

// ---------------------------------------------------------------------------------------------
// Phase → joint targets
// ---------------------------------------------------------------------------------------------

// duty_factor  D in (0, 1): stance share of the phase (PhaseNetwork: the gait's; Hopf: ½).
// stride_rad   per joint (hip yaw, hip pitch, knee), rad at stride = ±1 and amplitude 1.
// lift_rad     per joint, rad at the top of the swing (lift = 1).
// Zero joint angles = the neutral standing pose.
// lift_share  a in [0, 0.5): 0 gives the smooth swing below; a > 0 a lift–move–place swing
//             (climbers: a peeled foot must clear the surface before it moves).
struct LegShape {
  double duty_factor = 0.5;
  std::array<double, 3> stride_rad{};
  std::array<double, 3> lift_rad{};
  double lift_share = 0.0;
};

// stance:   θ in the stance part.
// progress: share of the current part done, [0, 1).
// stride:   [−1, 1], +1 = foot forward.   lift: [0, 1], 0 throughout stance.
// joint_rad[k] = amplitude·stride·stride_rad[k] + lift·lift_rad[k].
struct LegCommand {
  std::array<double, 3> joint_rad;
  bool stance;
  double progress;
  double stride;
  double lift;
};

// Throws std::invalid_argument if duty_factor is outside (0, 1) or any entry is not finite.
// Call it where the shape is loaded; ShapeLeg checks only the duty factor.
void ValidateLegShape(const LegShape& shape);

// With s = 2π(1−D) the end of swing and θ wrapped into [0, 2π):
//   swing,  p = θ/s:            stride = −cos(π·p)      lift = sin²(π·p)      (lift_share 0)
//   swing, lift–move–place (a = lift_share, r(u) = 3u² − 2u³ clamped to [0, 1]):
//           lift = r(p/a)·r((1 − p)/a)       stride = 2·r((p − a)/(1 − 2a)) − 1
//           the foot rises over p ∈ [0, a], moves over [a, 1 − a] at full lift, lands over
//           [1 − a, 1]; stride and lift are continuous, with zero rate at every joint.
//   stance, q = (θ − s)/(2πD):  stride = 1 − 2q         lift = 0
// Stance is linear so that the foot moves at constant speed against the ground: every leg in
// stance then pushes the body at the same speed, and attached pads do not fight each other
// (a cosine would have legs early and late in stance moving at different speeds, loading the
// pads in shear). Swing is a cosine so that the foot leaves and arrives with no speed along
// the stride and lift is sin² so that it rises and lands with zero vertical speed: a pad
// lands gently (adhesion's max approach speed). stride and lift are continuous at both
// transitions; the stride's speed jumps at touch-down and lift-off (the servos smooth it).
// Lift is not scaled by amplitude: a leg at a small stride still clears the surface.
// Throws std::invalid_argument for a duty factor outside (0, 1) or a non-finite θ.
LegCommand ShapeLeg(const LegShape& shape, double theta_rad, double amplitude);

}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_CPG_H_
