// Disturbances of the surface and the body that `climbsim bench robustness` varies (and any
// scenario may set): weak patches of the surface (scene.weak_patches), bumps on it
// (scene.roughness) and a payload on the body (payload_kg; applied by World). Every random
// choice is a hash of the scenario's seed and the item's integer coordinates (SplitMix64), so
// a layout needs no storage, is the same in every run with that seed, whatever the threads,
// and a lookup in the step allocates nothing.
#ifndef CLIMBSIM_SIM_SURFACE_H_
#define CLIMBSIM_SIM_SURFACE_H_

#include <cstdint>
#include <string>

#include "scenario/scenario.h"
#include "sim/world.h"

namespace climbsim::sim {

// A uniform draw in [0, 1) from (seed, stream, a, b): SplitMix64 of their mix.
double UnitDraw(uint64_t seed, uint64_t stream, int64_t a, int64_t b);

// Draw streams (so that the layouts of different disturbances are independent).
inline constexpr uint64_t kStreamWeakPatch = 1;
inline constexpr uint64_t kStreamBump = 2;
inline constexpr uint64_t kStreamPadFailure = 3;

// σ_T scale of the surface at (x, y) on the plane z = 0: params.fraction on a weak cell, else
// 1. Cell (i, j) = (floor(x/size_m), floor(y/size_m)) is weak when its draw < coverage.
double PatchStrength(const WeakPatchParams& params, int seed, double x_m, double y_m);

// The bumps of scene.roughness as <geom> lines for a <worldbody> (empty without roughness).
// Compiles robot and scene once to find the robot's starting footprint (initial pose
// included) and leaves out the bumps within 1 cm of it; bumps copy the friction of the
// scene's surface plane. Throws InputError at scene.roughness if no bump is left.
std::string RoughnessMjcf(const Scenario& scenario);

// How many bumps a compiled model holds (geoms named "bump_*"), and the largest top height.
int BumpCount(const mjModel* model, double* top_m = nullptr);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_SURFACE_H_
