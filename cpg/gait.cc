#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "cpg/cpg.h"
#include "cpg/internal/checks.h"

namespace climbsim::cpg {
namespace {

struct Preset {
  std::string_view name;
  int num_legs;
  Gait gait;
};

// docs/control.md's table, in the robots' leg orders (4: LF, RF, LH, RH; 6: L1, L2, L3, R1, R2,
// R3).
const std::vector<Preset>& Presets() {
  static const std::vector<Preset> presets = {
      {"trot", 4, {{0.0, 0.5, 0.5, 0.0}, 0.5}},
      {"lateral_sequence", 4, {{0.25, 0.75, 0.0, 0.5}, 0.75}},
      {"tripod", 6, {{0.0, 0.5, 0.0, 0.5, 0.0, 0.5}, 0.5}},
      {"tetrapod", 6, {{2.0 / 3.0, 1.0 / 3.0, 0.0, 1.0 / 3.0, 0.0, 2.0 / 3.0}, 2.0 / 3.0}},
      {"wave", 6, {{2.0 / 6.0, 1.0 / 6.0, 0.0, 5.0 / 6.0, 4.0 / 6.0, 3.0 / 6.0}, 5.0 / 6.0}},
  };
  return presets;
}

std::string JoinNames(int num_legs) {
  std::string joined;
  for (const std::string& name : GaitPresetNames(num_legs)) {
    joined += (joined.empty() ? "" : ", ") + name;
  }
  return joined.empty() ? "none" : joined;
}

}  // namespace

Gait GaitPreset(std::string_view name, int num_legs) {
  for (const Preset& preset : Presets()) {
    if (preset.name == name && preset.num_legs == num_legs) return preset.gait;
  }
  internal::Fail(GaitPresetProblem(name, num_legs));
}

std::string GaitPresetProblem(std::string_view name, int num_legs) {
  for (const Preset& preset : Presets()) {
    if (preset.name == name && preset.num_legs == num_legs) return "";
  }
  return "gait preset '" + std::string(name) + "' is not defined for " +
         std::to_string(num_legs) + " legs; presets for " + std::to_string(num_legs) +
         " legs: " + JoinNames(num_legs);
}

std::vector<std::string> GaitPresetNames(int num_legs) {
  std::vector<std::string> names;
  for (const Preset& preset : Presets()) {
    if (preset.num_legs == num_legs) names.emplace_back(preset.name);
  }
  return names;
}

Eigen::MatrixXd PhaseBiasFromOffsets(const std::vector<double>& offsets_cycles) {
  const int n = static_cast<int>(offsets_cycles.size());
  for (int i = 0; i < n; ++i) {
    internal::CheckFinite("offsets_cycles[" + std::to_string(i) + "]", offsets_cycles[i]);
  }
  Eigen::MatrixXd bias(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      bias(i, j) = internal::kTwoPi * (offsets_cycles[i] - offsets_cycles[j]);
    }
  }
  return bias;
}

Eigen::MatrixXd AllToAllCoupling(int num_oscillators, double weight_per_s) {
  if (num_oscillators < 1) internal::Fail("num_oscillators", ">= 1", num_oscillators);
  internal::CheckFinite("weight_per_s", weight_per_s);
  Eigen::MatrixXd coupling =
      Eigen::MatrixXd::Constant(num_oscillators, num_oscillators, weight_per_s);
  coupling.diagonal().setZero();
  return coupling;
}

PhaseNetworkParams PhaseNetworkParamsForGait(const Gait& gait, double frequency_hz,
                                             double coupling_per_s, double amplitude) {
  const int n = static_cast<int>(gait.offsets_cycles.size());
  PhaseNetworkParams params;
  params.frequency_hz = frequency_hz;
  params.coupling_per_s = AllToAllCoupling(n, coupling_per_s);
  params.phase_bias_rad = PhaseBiasFromOffsets(gait.offsets_cycles);
  params.target_amplitude = Eigen::VectorXd::Constant(n, amplitude);
  return params;
}

HopfFrequencies HopfFrequenciesForGait(double stride_frequency_hz, double duty_factor) {
  internal::CheckPositive("stride_frequency_hz", stride_frequency_hz);
  if (!(duty_factor > 0.0 && duty_factor < 1.0)) {
    internal::Fail("duty_factor", "in (0, 1)", duty_factor);
  }
  return {stride_frequency_hz / (2.0 * duty_factor),
          stride_frequency_hz / (2.0 * (1.0 - duty_factor))};
}

HopfNetworkParams HopfNetworkParamsForGait(const Gait& gait, double stride_frequency_hz,
                                           double coupling_per_s) {
  const int n = static_cast<int>(gait.offsets_cycles.size());
  const HopfFrequencies frequencies = HopfFrequenciesForGait(stride_frequency_hz, gait.duty_factor);
  HopfNetworkParams params;
  params.stance_frequency_hz = frequencies.stance_frequency_hz;
  params.swing_frequency_hz = frequencies.swing_frequency_hz;
  params.coupling_per_s = AllToAllCoupling(n, coupling_per_s);
  params.phase_bias_rad = PhaseBiasFromOffsets(gait.offsets_cycles);
  return params;
}

double TegotaeFeedback(double sigma_rad_per_n_s, double normal_load_n, double theta_rad) {
  return -sigma_rad_per_n_s * normal_load_n * std::cos(theta_rad);
}

}  // namespace climbsim::cpg
