// Load feedback (Tegotae) and the shaping of an oscillator's phase into a leg's joint targets
// (cpg/cpg.h has the phase convention).
#ifndef CLIMBSIM_CPG_LEG_SHAPE_H_
#define CLIMBSIM_CPG_LEG_SHAPE_H_

#include <array>

namespace climbsim::cpg {

// ---------------------------------------------------------------------------------------------
// Load feedback (Tegotae; Owaki et al. 2013, J R Soc Interface; Owaki and Ishiguro 2017,
// Sci Rep, doi 10.1038/s41598-017-00348-9)
// ---------------------------------------------------------------------------------------------

// −σ·N·cos θ, rad/s, to pass to Step as feedback_i. σ in rad/(N·s) (6 for Owaki's quadruped),
// N the leg's normal load in N (on a climber, the pad's normal or adhesive load), θ the leg's
// phase. Load draws the phase towards mid-stance, 3π/2 in Owaki's halves (swing [0, π),
// stance [π, 2π)): sped up before it, slowed after it, so a leg that carries load stays in
// stance and one that is unloaded swings on at its own rate. That is cpg/cpg.h's convention
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

#endif  // CLIMBSIM_CPG_LEG_SHAPE_H_
