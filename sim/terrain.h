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
// FillTerrain writes the heights into hfield_data after compile. The rock's lowest point lies
// kTerrainPlaneClearM above the scene's plane (z = 0, still there, beneath the rock), so the
// robot is lifted by that and the depth of that point below the mean; under each pad's
// starting place the rock is flattened to its mean (a disc of the pad's half-diagonal plus
// 5 mm, blended back over 20 mm), so a robot that starts attached starts on flat patches and
// steps onto rock with its first step. The heightfield copies the friction and contact
// softness of the scene's plane; boxes touch it through TerrainBoxContacts (below). A run
// folder's model.xml holds the heightfield's grid but not its heights (flat there).
#ifndef CLIMBSIM_SIM_TERRAIN_H_
#define CLIMBSIM_SIM_TERRAIN_H_

#include <mujoco/mujoco.h>

#include <vector>

#include "scenario/scenario.h"
#include "sim/world.h"

namespace climbsim::sim {

// The rock's lowest point lies this far above the scene's plane (m): a pad pressed into a
// hollow of the rock never touches the plane as well (two surfaces' contacts on one pad press
// it twice, and a flat heightfield would lie in the plane).
inline constexpr double kTerrainPlaneClearM = 0.002;

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
// penetration is sideways, so a flat pad pressed 0.2-0.5 mm onto a flat heightfield gets
// contacts with normals tilted up to 90° (measured: up to 7 of 17 on a 12.5 mm grid, up to 18
// of 50 on a 5 mm grid), and at most 50 contacts, cut to one side of the pad on a fine grid. A
// pad leaving the rock snags on them, and every prism under a face presses it: a flat
// heightfield held the walls' climbs to half the plane's. This collider takes the terrain's box
// pairs instead (mjCOLLISIONFUNC[HFIELD][BOX], installed before main; other heightfields keep
// MuJoCo's):
//   - each box corner below the rock's surface: a contact along the surface's normal there, at
//     the distance from the corner to that triangle's plane;
//   - each grid point of the rock inside the box that is a peak seen from the box's face
//     towards the rock (no neighbour reaches further into the box, some less far): a contact
//     along that face's normal, at the point's depth behind it;
// the deepest mjMAXCONPAIR of them, each at the midpoint of its penetration, normal from the
// rock to the box. A flat or evenly sloping patch has no peaks, so a box on a flat heightfield
// gets exactly the plane's corner contacts. The surface is MuJoCo's (each cell split along its
// diagonal (c, r)-(c + 1, r + 1), as mj_rayHfield and the renderer split it). Allocation-free.
// Returns the number of contacts written to con.
int TerrainBoxContacts(const mjModel* m, const mjData* d, mjContact* con, int g_hfield, int g_box,
                       mjtNum margin);

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TERRAIN_H_
