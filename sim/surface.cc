#include "sim/surface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

namespace climbsim::sim {
namespace {

// How far a bump's box reaches below the surface: deeper than any robot part sinks into it.
constexpr double kBumpRootDepthM = 0.05;

uint64_t SplitMix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// The robot's starting footprint on the plane z = 0: x_min, x_max, y_min, y_max of every
// geom of the robot (bounding spheres), in its initial pose.
std::array<double, 4> Footprint(World& world) {
  const mjModel* m = world.model();
  mjData* d = world.data();
  mj_kinematics(m, d);
  const int root = world.robot().base_body;
  std::array<double, 4> box{std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::max(),
                            -std::numeric_limits<double>::max()};
  for (int g = 0; g < m->ngeom; ++g) {
    const int b = m->geom_bodyid[g];
    if (b == 0 || m->body_rootid[b] != m->body_rootid[root]) continue;
    const double r = m->geom_rbound[g];
    box[0] = std::min(box[0], d->geom_xpos[3 * g] - r);
    box[1] = std::max(box[1], d->geom_xpos[3 * g] + r);
    box[2] = std::min(box[2], d->geom_xpos[3 * g + 1] - r);
    box[3] = std::max(box[3], d->geom_xpos[3 * g + 1] + r);
  }
  return box;
}

// Friction of the scene's first plane (the surface), as MJCF text.
std::string SurfaceFriction(const mjModel* m) {
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == 0 && m->geom_type[g] == mjGEOM_PLANE) {
      char buf[96];
      std::snprintf(buf, sizeof(buf), "%.17g %.17g %.17g", m->geom_friction[3 * g],
                    m->geom_friction[3 * g + 1], m->geom_friction[3 * g + 2]);
      return buf;
    }
  }
  return "1 0.005 0.0001";
}

}  // namespace

double UnitDraw(uint64_t seed, uint64_t stream, int64_t a, int64_t b) {
  uint64_t z = SplitMix64(seed ^ (stream * 0xD1B54A32D192ED03ull));
  z = SplitMix64(z ^ static_cast<uint64_t>(a));
  z = SplitMix64(z ^ static_cast<uint64_t>(b));
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

double PatchStrength(const WeakPatchParams& p, int seed, double x_m, double y_m) {
  const auto i = static_cast<int64_t>(std::floor(x_m / p.size_m));
  const auto j = static_cast<int64_t>(std::floor(y_m / p.size_m));
  return UnitDraw(static_cast<uint64_t>(seed), kStreamWeakPatch, i, j) < p.coverage ? p.fraction
                                                                                    : 1.0;
}

std::string RoughnessMjcf(const Scenario& s) {
  if (!s.scene.roughness) return "";
  const RoughnessParams& r = *s.scene.roughness;
  const std::unique_ptr<CompiledModel> base = CompiledModel::Build(s, MjcfAdditions{});
  World world(*base, s);
  const std::array<double, 4> foot = Footprint(world);
  const double margin = 0.01;
  const std::string friction = SurfaceFriction(world.model());
  const int nx = static_cast<int>(std::ceil((r.extent_m[1] - r.extent_m[0]) / r.spacing_m));
  const int ny = static_cast<int>(std::ceil((r.extent_m[3] - r.extent_m[2]) / r.spacing_m));
  const double half = 0.5 * r.size_m;
  const double play = r.spacing_m - r.size_m;  // how far a bump may move within its cell
  // A bump is a box from its top down to kBumpRootDepthM inside the surface, not a slab as thin
  // as its height: MuJoCo's box-box contact pushes out along the shallower overlap, so a pad
  // that a soft contact sinks deeper than half a slab's height (a 0.5 mm bump, 1 mm sunk) was
  // pushed into the surface and pinned there. The root is inside the surface's own body,
  // which it never collides with.
  const double center_z = 0.5 * (r.height_m - kBumpRootDepthM);
  const double half_z = 0.5 * (r.height_m + kBumpRootDepthM);
  std::string xml;
  int count = 0;
  char buf[512];
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const double x = r.extent_m[0] + i * r.spacing_m + half +
                       play * UnitDraw(static_cast<uint64_t>(s.seed), kStreamBump, i, 2 * j);
      const double y = r.extent_m[2] + j * r.spacing_m + half +
                       play * UnitDraw(static_cast<uint64_t>(s.seed), kStreamBump, i, 2 * j + 1);
      if (x + half > foot[0] - margin && x - half < foot[1] + margin &&
          y + half > foot[2] - margin && y - half < foot[3] + margin) {
        continue;
      }
      std::snprintf(buf, sizeof(buf),
                    "    <geom name=\"bump_%d_%d\" type=\"box\" pos=\"%.17g %.17g %.17g\" "
                    "size=\"%.17g %.17g %.17g\" contype=\"1\" conaffinity=\"2\" condim=\"3\" "
                    "friction=\"%s\" rgba=\"0.55 0.5 0.45 1\"/>\n",
                    i, j, x, y, center_z, half, half, half_z, friction.c_str());
      xml += buf;
      ++count;
    }
  }
  if (count == 0) {
    throw ScenarioError(s, "scene.roughness",
                        "no bump is left outside the robot's starting footprint: widen extent_m");
  }
  return xml;
}

int BumpCount(const mjModel* m, double* top_m) {
  int n = 0;
  double top = 0.0;
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    if (name == nullptr || std::strncmp(name, "bump_", 5) != 0) continue;
    ++n;
    top = std::max(top, m->geom_pos[3 * g + 2] + m->geom_size[3 * g + 2]);
  }
  if (top_m != nullptr) *top_m = top;
  return n;
}

}  // namespace climbsim::sim
