// Gaits as phase offsets, their presets, and the phase-bias and coupling matrices built from
// them (cpg/cpg.h has the conventions).
#ifndef CLIMBSIM_CPG_GAIT_H_
#define CLIMBSIM_CPG_GAIT_H_

#include <Eigen/Core>
#include <string>
#include <string_view>
#include <vector>

namespace climbsim::cpg {

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
// What GaitPreset would throw for (name, num_legs), or "" when the preset is defined: a
// caller that reports errors its own way checks first instead of catching.
std::string GaitPresetProblem(std::string_view name, int num_legs);

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

}  // namespace climbsim::cpg

#endif  // CLIMBSIM_CPG_GAIT_H_
