// ROUGH ROCK (scene.terrain, keys in sim/terrain_params.h): a seeded Gaussian random surface
// as a MuJoCo heightfield in place of a plane scene's flat surface (floor, wall, ceiling,
// incline: all have their surface at z = 0 with normal +z).
//
// SYNTHESIS. On a periodic grid of 2^a × 2^b points (the extent, rounded up), each Fourier
// coefficient gets the amplitude √C(q) of the von Karman spectrum and a phase drawn from
// std::mt19937_64(seed), mirrored so that the inverse transform (Eigen's FFT) is real; the
// heights are then shifted to mean 0 and scaled to RMS σ exactly. Fixed amplitudes: the
// sampled spectrum is the closed form's, only the phases are random.
//
// IN THE MODEL. MuJoCo 2.2.2's MJCF has no `elevation` on <hfield> (its schema rejects it),
// so the composed MJCF declares the heightfield (its grid and size) and the geom, and
// FillTerrain writes the heights into hfield_data after compile. The rock's lowest point rests
// on the scene's plane (z = 0, still there, beneath the rock), so the robot is lifted by the
// depth of that point below the mean; under each pad's starting place the rock is flattened to
// its mean (a disc of the pad's half-diagonal plus 5 mm, blended back over 20 mm), so a robot
// that starts attached starts on flat patches and steps onto rock with its first step. The
// heightfield copies the friction and contact softness of the scene's plane. A run folder's
// model.xml holds the heightfield's grid but not its heights (flat there).
#ifndef CLIMBSIM_SIM_TERRAIN_H_
#define CLIMBSIM_SIM_TERRAIN_H_

#include <mujoco/mujoco.h>

#include <vector>

#include "scenario/scenario.h"
#include "sim/world.h"

namespace climbsim::sim {

// The periodic rock on an nx × ny grid of pitch params.grid_m (nx, ny powers of two),
// h[j·nx + i] at (i·grid_m, j·grid_m): mean 0, RMS params.rms_m.
std::vector<double> RockField(const TerrainParams& params, int nx, int ny);

// R(r)/σ² of the spectrum (the closed form the field follows).
double RockCorrelation(const TerrainParams& params, double r_m);

// The heightfield's columns (along x) and rows (along y) over extent_m.
int TerrainColumns(const TerrainParams& params);
int TerrainRows(const TerrainParams& params);

// The heightfield asset and geom of scene.terrain (nothing without it). The asset's comment
// names every key and the initial pose, so that models of different rocks differ in text.
void AddTerrainMjcf(const Scenario& scenario, MjcfAdditions* additions);

// Writes the heights of scene.terrain into the compiled model (see the file comment) and lifts
// the robot's spawn (qpos0); nothing without scene.terrain.
void FillTerrain(const Scenario& scenario, const RobotInfo& robot, mjModel* model);

// The terrain's geom id in a model; −1 when it has none.
int TerrainGeom(const mjModel* model);

// CONTACTS OF A BOX ON THE TERRAIN (a pad, a body box). MuJoCo 2.2.2 collides a convex geom with
// a heightfield prism by prism (mjc_ConvexHField, the libccd MPR penetration of each triangular
// prism): where a box's edge overlaps a prism by less than it is pressed in, the least
// penetration is sideways, so a flat pad pressed 0.2 mm onto a flat heightfield gets contacts
// with normals tilted up to 90° (measured: 1 to 7 of 17 on a 12.5 mm grid, 3 to 18 of 50 on a
// 5 mm grid), and at most 50 contacts, cut to one side of the pad on a fine grid. A pad sliding
// off the rock snags on them. This collider takes the terrain's box pairs instead
// (mjCOLLISIONFUNC[HFIELD][BOX], installed before main; other heightfields keep MuJoCo's):
//   - each box corner below the rock's surface: a contact along the surface's normal there, at
//     the distance from the corner to that triangle's plane;
//   - each grid point of the rock inside the box: a contact along the normal of the box face
//     that faces the rock, at the point's depth behind that face;
// the deepest mjMAXCONPAIR of them, each at the midpoint of its penetration, normal from the
// rock to the box. The surface is MuJoCo's (the cells split along the diagonal (c, r)-(c + 1,
// r + 1), as mj_rayHfield and the renderer split them): on a flat heightfield a box gets the
// plane's contacts. Allocation-free. Returns the number of contacts written to con.
int TerrainBoxContacts(const mjModel* m, const mjData* d, mjContact* con, int g_hfield, int g_box,
                       mjtNum margin);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TERRAIN_H_
