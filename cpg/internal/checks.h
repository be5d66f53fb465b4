// Internal to climbsim::cpg: parameter checks with messages that name the field and the value
// ("PhaseNetworkParams.frequency_hz must be > 0, got -1"), and angle wrapping.
#ifndef CLIMBSIM_CPG_INTERNAL_CHECKS_H_
#define CLIMBSIM_CPG_INTERNAL_CHECKS_H_

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace climbsim::cpg {
struct StepperParams;   // oscillator_network.h
enum class StepStatus;  // oscillator_network.h
}  // namespace climbsim::cpg

namespace climbsim::cpg::internal {

inline constexpr double kTwoPi = 6.283185307179586476925286766559;
inline constexpr double kPi = 3.141592653589793238462643383279;

// θ into [0, 2π). The final test catches θ a hair below 0, for which θ + 2π rounds to 2π.
double WrapTwoPi(double theta_rad);
// Δ into [−π, π).
double WrapPi(double delta_rad);

// Shortest round-trip text of a value ("0.1", "1e-08", "nan").
std::string Num(double value);

[[noreturn]] void Fail(std::string_view field, std::string_view requirement, double got);
[[noreturn]] void Fail(std::string_view message);

void CheckFinite(std::string_view field, double value);
void CheckPositive(std::string_view field, double value);     // finite and > 0
void CheckNonNegative(std::string_view field, double value);  // finite and >= 0
// rows × cols == n × n and all entries finite.
void CheckSquare(std::string_view field, const Eigen::MatrixXd& m, int n, std::string_view why_n);
// All entries finite, zero diagonal.
void CheckZeroDiagonal(std::string_view field, const Eigen::MatrixXd& m);
// StepperParams as oscillator_network.h documents; owner is "PhaseNetworkParams" or "HopfNetworkParams".
void CheckStepperParams(std::string_view owner, const StepperParams& params);

// A network's status after a step: a non-finite state outranks a Dopri5 step-size collapse.
StepStatus StepStatusOf(bool state_finite, bool step_finished);

// What a network's Step holds constant over the step: the feedback and the held flags, one per
// oscillator, sized once. Latch checks a Step's arguments (owner names the network in
// messages) and returns true when any value changed: the right-hand side changed with it, so
// Dopri5's carried-over derivative is stale.
class StepInputs {
 public:
  explicit StepInputs(int n) : feedback_rad_per_s_(n, 0.0), held_(n, 0) {}
  bool Latch(std::string_view owner, double dt_s, std::span<const double> feedback_rad_per_s,
             std::span<const uint8_t> held);
  void Clear();
  double feedback(int i) const { return feedback_rad_per_s_[i]; }
  bool held(int i) const { return held_[i] != 0; }

 private:
  std::vector<double> feedback_rad_per_s_;
  std::vector<uint8_t> held_;
};

}  // namespace climbsim::cpg::internal

#endif  // CLIMBSIM_CPG_INTERNAL_CHECKS_H_
