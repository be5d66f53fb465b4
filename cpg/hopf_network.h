// Hopf oscillators with stance and swing frequencies (Righetti and Ijspeert 2008); cpg/cpg.h
// has the conventions.
#ifndef CLIMBSIM_CPG_HOPF_NETWORK_H_
#define CLIMBSIM_CPG_HOPF_NETWORK_H_

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "cpg/gait.h"
#include "cpg/internal/checks.h"
#include "cpg/internal/odeint_driver.h"
#include "cpg/oscillator_network.h"

namespace climbsim::cpg {

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
// of cpg/cpg.h (swing first) is  θ = ϑ + π  wrapped to [0, 2π): swing θ ∈ [0, π), stance
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

  // Places oscillator i at phase θ_i (cpg/cpg.h's convention) and radius amplitude_i·sqrt(μ):
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
  void PrepareWarp(const double* x, const double* y);
  void CouplingTarget(int i, int j, bool warped, const double* x, const double* y,
                      double* target_x, double* target_y) const;
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

}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_HOPF_NETWORK_H_
