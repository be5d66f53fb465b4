#include "sim/terrain.h"

#include <unsupported/Eigen/FFT>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstring>
#include <random>

namespace climbsim::sim {
namespace {

constexpr char kTerrainName[] = "climbsim_terrain";
constexpr double kTopRms = 12.0;      // the declared top: 12 σ (a Gaussian's range over 1e6 points ≈ 10 σ)
constexpr double kBaseM = 0.01;       // the rock's thickness below its lowest point
constexpr double kPadClearM = 0.005;  // flat beyond a starting pad's half-diagonal...
constexpr double kBlendM = 0.02;      // ...then blended back to rock over this
constexpr int kMaxContacts = 1000;    // the model's contact buffer (MuJoCo's default: 100)

int PowerOfTwoAtLeast(int n) {
  int p = 1;
  while (p < n) p *= 2;
  return p;
}

// A uniform draw in [0, 1) from the generator's 53 high bits (the same on every machine).
double Unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Spectrum coefficients: amplitude √C(q), phase drawn per coefficient and mirrored
// (c(−q) = conj c(q)) so that the inverse transform is real. Column-major in y: [j·nx + i].
std::vector<std::complex<double>> Coefficients(const TerrainParams& p, int nx, int ny) {
  std::mt19937_64 rng(static_cast<uint64_t>(p.seed));
  std::vector<double> phase(static_cast<size_t>(nx) * ny);
  for (double& ph : phase) ph = 2.0 * M_PI * Unit(rng);
  std::vector<std::complex<double>> c(phase.size());
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const int mi = (nx - i) % nx, mj = (ny - j) % ny;
      const size_t k = static_cast<size_t>(j) * nx + i, mk = static_cast<size_t>(mj) * nx + mi;
      if (k == mk) continue;  // self-mirrored (the mean, the Nyquist corners): left out
      const double qx = 2.0 * M_PI * (i <= nx / 2 ? i : i - nx) / (nx * p.grid_m);
      const double qy = 2.0 * M_PI * (j <= ny / 2 ? j : j - ny) / (ny * p.grid_m);
      const double q2 = (qx * qx + qy * qy) * p.correlation_m * p.correlation_m;
      const double amplitude = std::pow(1.0 + q2, -0.5 * (1.0 + p.hurst));
      const double ph = k < mk ? phase[k] : -phase[mk];
      c[k] = std::polar(amplitude, ph);
    }
  }
  return c;
}

// In-place 2-D inverse transform (rows, then columns).
void Inverse2d(int nx, int ny, std::vector<std::complex<double>>* c) {
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> in, out;
  for (int j = 0; j < ny; ++j) {
    in.assign(c->begin() + static_cast<long>(j) * nx, c->begin() + static_cast<long>(j + 1) * nx);
    fft.inv(out, in);
    std::copy(out.begin(), out.end(), c->begin() + static_cast<long>(j) * nx);
  }
  in.resize(ny);
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) in[j] = (*c)[static_cast<size_t>(j) * nx + i];
    fft.inv(out, in);
    for (int j = 0; j < ny; ++j) (*c)[static_cast<size_t>(j) * nx + i] = out[j];
  }
}

// The starting pads' centres (x, y) on the plane, the scenario's initial pose applied as
// World applies it (offset, then yaw about the base), and the largest half-diagonal.
std::vector<std::array<double, 2>> StartPads(const Scenario& s, const RobotInfo& r,
                                             const mjModel* m, double* half_diagonal_m) {
  mjData* d = mj_makeData(m);
  mj_kinematics(m, d);
  const double bx = m->qpos0[r.root_qpos_adr], by = m->qpos0[r.root_qpos_adr + 1];
  const double yaw = s.initial.yaw_deg * M_PI / 180.0;
  std::vector<std::array<double, 2>> pads;
  *half_diagonal_m = 0.0;
  for (const LegInfo& leg : r.legs) {
    const int g = leg.pad_geom;
    const double x = d->geom_xpos[3 * g] - bx, y = d->geom_xpos[3 * g + 1] - by;
    pads.push_back({bx + s.initial.offset_m[0] + std::cos(yaw) * x - std::sin(yaw) * y,
                    by + s.initial.offset_m[1] + std::sin(yaw) * x + std::cos(yaw) * y});
    *half_diagonal_m =
        std::max(*half_diagonal_m, std::hypot(m->geom_size[3 * g], m->geom_size[3 * g + 1]));
  }
  mj_deleteData(d);
  return pads;
}

// The smooth step 0 → 1 over [0, 1].
double Blend(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// Copies friction and contact softness of the scene's first plane (the surface) to geom g.
void CopySurfaceContact(mjModel* m, int g) {
  for (int p = 0; p < m->ngeom; ++p) {
    if (m->geom_bodyid[p] != 0 || m->geom_type[p] != mjGEOM_PLANE) continue;
    std::memcpy(m->geom_friction + 3 * g, m->geom_friction + 3 * p, 3 * sizeof(mjtNum));
    std::memcpy(m->geom_solref + mjNREF * g, m->geom_solref + mjNREF * p, mjNREF * sizeof(mjtNum));
    std::memcpy(m->geom_solimp + mjNIMP * g, m->geom_solimp + mjNIMP * p, mjNIMP * sizeof(mjtNum));
    m->geom_condim[g] = m->geom_condim[p];
    return;
  }
}

// MuJoCo's own collider of a convex geom with a heightfield (mjc_ConvexHField in 2.2.2), for
// the pairs TerrainBoxContacts does not take.
mjfCollision g_hfield_box_builtin = nullptr;

// The terrain's heights and their triangulation (hfield frame): MuJoCo's, each grid cell
// split along its diagonal from (c, r) to (c + 1, r + 1), as its collider and mj_rayHfield
// split it.
struct HfieldGrid {
  const float* data;
  int nrow, ncol;
  double sx, sy, sz, dx, dy;

  HfieldGrid(const mjModel* m, int g) {
    const int hf = m->geom_dataid[g];
    data = m->hfield_data + m->hfield_adr[hf];
    nrow = m->hfield_nrow[hf];
    ncol = m->hfield_ncol[hf];
    sx = m->hfield_size[4 * hf];
    sy = m->hfield_size[4 * hf + 1];
    sz = m->hfield_size[4 * hf + 2];
    dx = 2.0 * sx / (ncol - 1);
    dy = 2.0 * sy / (nrow - 1);
  }
  double At(int r, int c) const { return data[r * ncol + c] * sz; }
  double X(int c) const { return dx * c - sx; }
  double Y(int r) const { return dy * r - sy; }
  bool Inside(double x, double y) const { return std::abs(x) <= sx && std::abs(y) <= sy; }

  // Height at (x, y) inside the grid and the triangle's upward unit normal.
  double Surface(double x, double y, double normal[3]) const {
    const double u = (x + sx) / dx, v = (y + sy) / dy;
    const int c = std::clamp(static_cast<int>(std::floor(u)), 0, ncol - 2);
    const int r = std::clamp(static_cast<int>(std::floor(v)), 0, nrow - 2);
    const double fu = u - c, fv = v - r;
    const double h00 = At(r, c), h10 = At(r, c + 1), h01 = At(r + 1, c), h11 = At(r + 1, c + 1);
    const bool lower = fu >= fv;  // the triangle (c, r), (c + 1, r), (c + 1, r + 1)
    const double sx_slope = lower ? (h10 - h00) / dx : (h11 - h01) / dx;
    const double sy_slope = lower ? (h11 - h10) / dy : (h01 - h00) / dy;
    const double inv = 1.0 / std::sqrt(1.0 + sx_slope * sx_slope + sy_slope * sy_slope);
    normal[0] = -sx_slope * inv;
    normal[1] = -sy_slope * inv;
    normal[2] = inv;
    return lower ? h00 + fu * (h10 - h00) + fv * (h11 - h10)
                 : h00 + fv * (h01 - h00) + fu * (h11 - h01);
  }
};

// Adds one contact (hfield frame: point, normal from the rock to the box, distance) to con,
// keeping the mjMAXCONPAIR deepest.
void AddContact(const double* pos1, const double* mat1, const double p[3], const double n[3],
                double dist, mjContact* con, int* count) {
  int slot = *count;
  if (slot == mjMAXCONPAIR) {
    slot = 0;
    for (int i = 1; i < mjMAXCONPAIR; ++i) {
      if (con[i].dist > con[slot].dist) slot = i;
    }
    if (con[slot].dist <= dist) return;
  } else {
    ++*count;
  }
  mjContact& c = con[slot];
  c.dist = dist;
  mju_rotVecMat(c.pos, p, mat1);
  mju_addTo3(c.pos, pos1);
  mju_rotVecMat(c.frame, n, mat1);
  mju_zero3(c.frame + 3);
}

// The box's corners under the rock: normal the rock's, at the point under the corner.
void CornerContacts(const HfieldGrid& grid, const double* pos1, const double* mat1,
                    const double box_pos[3], const double box_rot[9], const double* size,
                    double margin, mjContact* con, int* count) {
  for (int k = 0; k < 8; ++k) {
    const double local[3] = {(k & 1 ? 1 : -1) * size[0], (k & 2 ? 1 : -1) * size[1],
                             (k & 4 ? 1 : -1) * size[2]};
    double p[3];
    mju_rotVecMat(p, local, box_rot);
    mju_addTo3(p, box_pos);
    if (!grid.Inside(p[0], p[1])) continue;
    double n[3];
    const double dist = (p[2] - grid.Surface(p[0], p[1], n)) * n[2];
    if (dist >= margin) continue;
    const double mid[3] = {p[0] - 0.5 * dist * n[0], p[1] - 0.5 * dist * n[1],
                           p[2] - 0.5 * dist * n[2]};
    AddContact(pos1, mat1, mid, n, dist, con, count);
  }
}

// The box's face towards the rock (the one whose outward normal points most down the hfield's
// z), in the hfield frame.
struct BoxFace {
  const double* box_pos;
  const double* box_rot;  // columns: the box axes in the hfield frame
  const double* size;
  int axis = 0;
  double sign = 1.0;  // outward normal = sign · box axis `axis`

  BoxFace(const double box_pos_in[3], const double box_rot_in[9], const double* size_in)
      : box_pos(box_pos_in), box_rot(box_rot_in), size(size_in) {
    for (int k = 1; k < 3; ++k) {
      if (std::abs(box_rot[6 + k]) > std::abs(box_rot[6 + axis])) axis = k;
    }
    sign = box_rot[6 + axis] > 0 ? -1.0 : 1.0;
  }
  // Signed distance of hfield point v beyond the face (< 0: behind it, inside the box).
  double Beyond(const double v[3]) const {
    double along = 0.0;
    for (int i = 0; i < 3; ++i) along += box_rot[3 * i + axis] * (v[i] - box_pos[i]);
    return sign * along - size[axis];
  }
  // Whether v lies within the face's outline (the box's other two axes).
  bool Over(const double v[3]) const {
    for (int k : {(axis + 1) % 3, (axis + 2) % 3}) {
      double along = 0.0;
      for (int i = 0; i < 3; ++i) along += box_rot[3 * i + k] * (v[i] - box_pos[i]);
      if (std::abs(along) > size[k]) return false;
    }
    return true;
  }
};

// Whether grid point (r, c) is a peak of the rock seen from the face: no neighbour reaches
// further into the box, and some neighbour less far (beyond rounding). A flat or evenly
// sloping patch has none, so a face on it gets its corners' contacts only, as on a plane.
bool FacePeak(const HfieldGrid& grid, const BoxFace& face, int r, int c, double beyond) {
  constexpr double kTieM = 1e-9;
  bool lower = false;
  for (int dr = -1; dr <= 1; ++dr) {
    for (int dc = -1; dc <= 1; ++dc) {
      const int rr = r + dr, cc = c + dc;
      if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= grid.nrow || cc >= grid.ncol) continue;
      const double w[3] = {grid.X(cc), grid.Y(rr), grid.At(rr, cc)};
      const double b = face.Beyond(w);
      if (b < beyond - kTieM) return false;
      lower |= b > beyond + kTieM;
    }
  }
  return lower;
}

// The rock's peaks inside the box, pushed out through the face towards the rock: normal that
// face's.
void PeakContacts(const HfieldGrid& grid, const double* pos1, const double* mat1,
                  const BoxFace& face, double margin, mjContact* con, int* count) {
  const double n[3] = {-face.sign * face.box_rot[face.axis],
                       -face.sign * face.box_rot[3 + face.axis],
                       -face.sign * face.box_rot[6 + face.axis]};
  int lo[2], hi[2];
  for (int i = 0; i < 2; ++i) {
    const double half = std::abs(face.box_rot[3 * i]) * face.size[0] +
                        std::abs(face.box_rot[3 * i + 1]) * face.size[1] +
                        std::abs(face.box_rot[3 * i + 2]) * face.size[2];
    const double origin = i == 0 ? grid.sx : grid.sy, step = i == 0 ? grid.dx : grid.dy;
    const int last = i == 0 ? grid.ncol - 1 : grid.nrow - 1;
    lo[i] = std::max(0, static_cast<int>(std::ceil((face.box_pos[i] - half + origin) / step)));
    hi[i] = std::min(last, static_cast<int>(std::floor((face.box_pos[i] + half + origin) / step)));
  }
  for (int r = lo[1]; r <= hi[1]; ++r) {
    for (int c = lo[0]; c <= hi[0]; ++c) {
      const double v[3] = {grid.X(c), grid.Y(r), grid.At(r, c)};
      const double dist = face.Beyond(v);
      if (dist >= margin || dist < -2.0 * face.size[face.axis] || !face.Over(v)) continue;
      if (!FacePeak(grid, face, r, c, dist)) continue;
      const double mid[3] = {v[0] + 0.5 * dist * n[0], v[1] + 0.5 * dist * n[1],
                             v[2] + 0.5 * dist * n[2]};
      AddContact(pos1, mat1, mid, n, dist, con, count);
    }
  }
}

// mjCOLLISIONFUNC[HFIELD][BOX]: the terrain against a box (TerrainBoxContacts); every other
// heightfield as MuJoCo collides it.
int HfieldBox(const mjModel* m, const mjData* d, mjContact* con, int g1, int g2, mjtNum margin) {
  if (std::strcmp(m->names + m->name_geomadr[g1], kTerrainName) != 0) {
    return g_hfield_box_builtin(m, d, con, g1, g2, margin);
  }
  return TerrainBoxContacts(m, d, con, g1, g2, margin);
}

// Installed before main, while no thread steps a model: the table is MuJoCo's global.
const bool g_hfield_box_installed = [] {
  g_hfield_box_builtin = mjCOLLISIONFUNC[mjGEOM_HFIELD][mjGEOM_BOX];
  mjCOLLISIONFUNC[mjGEOM_HFIELD][mjGEOM_BOX] = HfieldBox;
  return true;
}();

}  // namespace

std::vector<double> RockField(const TerrainParams& p, int nx, int ny) {
  std::vector<std::complex<double>> c = Coefficients(p, nx, ny);
  Inverse2d(nx, ny, &c);
  std::vector<double> h(c.size());
  double mean = 0.0;
  for (size_t k = 0; k < c.size(); ++k) mean += (h[k] = c[k].real());
  mean /= static_cast<double>(h.size());
  double sq = 0.0;
  for (double& v : h) {
    v -= mean;
    sq += v * v;
  }
  const double scale = p.rms_m / std::sqrt(sq / static_cast<double>(h.size()));
  for (double& v : h) v *= scale;
  return h;
}

double RockCorrelation(const TerrainParams& p, double r_m) {
  if (r_m <= 0.0) return 1.0;
  const double u = r_m / p.correlation_m;
  return std::pow(2.0, 1.0 - p.hurst) / std::tgamma(p.hurst) * std::pow(u, p.hurst) *
         std::cyl_bessel_k(p.hurst, u);
}

int TerrainColumns(const TerrainParams& p) {
  return static_cast<int>(std::ceil((p.extent_m[1] - p.extent_m[0]) / p.grid_m)) + 1;
}
int TerrainRows(const TerrainParams& p) {
  return static_cast<int>(std::ceil((p.extent_m[3] - p.extent_m[2]) / p.grid_m)) + 1;
}

void AddTerrainMjcf(const Scenario& s, MjcfAdditions* add) {
  if (!s.scene.terrain) return;
  const TerrainParams& t = *s.scene.terrain;
  const int nc = TerrainColumns(t), nr = TerrainRows(t);
  const double hx = 0.5 * (nc - 1) * t.grid_m, hy = 0.5 * (nr - 1) * t.grid_m;
  char buf[1024];
  std::snprintf(buf, sizeof(buf),
                "  <!-- climbsim terrain: rms_m %.17g correlation_m %.17g hurst %.17g seed %d "
                "grid_m %.17g; start pose %.17g %.17g %.17g yaw %.17g. Heights are written "
                "after compile (MuJoCo 2.2.2 MJCF has no elevation): flat in this file. A pad\n"
                "       on rock makes up to 50 contacts (MuJoCo's most per pair): room for them. -->\n"
                "  <size nconmax=\"%d\" njmax=\"%d\"/>\n"
                "  <asset>\n    <hfield name=\"%s\" nrow=\"%d\" ncol=\"%d\" size=\"%.17g %.17g %.17g %.17g\"/>\n"
                "  </asset>\n",
                t.rms_m, t.correlation_m, t.hurst, t.seed, t.grid_m, s.initial.offset_m[0],
                s.initial.offset_m[1], s.initial.offset_m[2], s.initial.yaw_deg, kMaxContacts,
                3 * kMaxContacts + 500, kTerrainName, nr,
                nc, hx, hy, kTopRms * t.rms_m, kBaseM);
  add->top += buf;
  std::snprintf(buf, sizeof(buf),
                "    <geom name=\"%s\" type=\"hfield\" hfield=\"%s\" pos=\"%.17g %.17g %.17g\" "
                "contype=\"1\" conaffinity=\"2\" condim=\"3\" rgba=\"0.55 0.5 0.45 1\"/>\n",
                kTerrainName, kTerrainName, t.extent_m[0] + hx, t.extent_m[2] + hy,
                kTerrainPlaneClearM);
  add->worldbody += buf;
}

void FillTerrain(const Scenario& s, const RobotInfo& r, mjModel* m) {
  const int g = TerrainGeom(m);
  if (!s.scene.terrain || g < 0) return;
  const TerrainParams& t = *s.scene.terrain;
  const int hf = m->geom_dataid[g];
  const int nr = m->hfield_nrow[hf], nc = m->hfield_ncol[hf];
  const int nx = PowerOfTwoAtLeast(nc), ny = PowerOfTwoAtLeast(nr);
  const std::vector<double> field = RockField(t, nx, ny);
  double half_diagonal = 0.0;
  const std::vector<std::array<double, 2>> pads = StartPads(s, r, m, &half_diagonal);
  std::vector<double> h(static_cast<size_t>(nr) * nc);
  double low = 0.0, high = 0.0;
  for (int j = 0; j < nr; ++j) {
    for (int i = 0; i < nc; ++i) {
      const double x = t.extent_m[0] + i * t.grid_m, y = t.extent_m[2] + j * t.grid_m;
      double w = 1.0;
      for (const auto& p : pads) {
        const double d = std::hypot(x - p[0], y - p[1]) - half_diagonal - kPadClearM;
        w = std::min(w, Blend(d / kBlendM));
      }
      const double v = w * field[static_cast<size_t>(j) * nx + i];
      h[static_cast<size_t>(j) * nc + i] = v;
      low = std::min(low, v);
      high = std::max(high, v);
    }
  }
  const double top = std::min(high - low, kTopRms * t.rms_m);
  float* data = m->hfield_data + m->hfield_adr[hf];
  for (size_t k = 0; k < h.size(); ++k) {
    data[k] = static_cast<float>(std::min(1.0, (h[k] - low) / top));
  }
  m->hfield_size[4 * hf + 2] = top;
  CopySurfaceContact(m, g);
  // The rock's mean plane is kTerrainPlaneClearM − low above the scene's plane: the robot
  // starts that much higher.
  m->qpos0[r.root_qpos_adr + 2] += kTerrainPlaneClearM - low;
}

int TerrainGeom(const mjModel* m) {
  const int g = mj_name2id(m, mjOBJ_GEOM, kTerrainName);
  return g >= 0 && m->geom_type[g] == mjGEOM_HFIELD ? g : -1;
}

int TerrainBoxContacts(const mjModel* m, const mjData* d, mjContact* con, int g_hfield, int g_box,
                       mjtNum margin) {
  const double* pos1 = d->geom_xpos + 3 * g_hfield;
  const double* mat1 = d->geom_xmat + 9 * g_hfield;
  // The box in the hfield frame: its centre and its axes (columns).
  double rel[3], box_pos[3], box_rot[9];
  mju_sub3(rel, d->geom_xpos + 3 * g_box, pos1);
  mju_rotVecMatT(box_pos, rel, mat1);
  mju_mulMatTMat(box_rot, mat1, d->geom_xmat + 9 * g_box, 3, 3, 3);
  const HfieldGrid grid(m, g_hfield);
  const double* size = m->geom_size + 3 * g_box;
  const double rbound = m->geom_rbound[g_box];
  if (box_pos[2] - rbound > grid.sz + margin || std::abs(box_pos[0]) - rbound > grid.sx ||
      std::abs(box_pos[1]) - rbound > grid.sy) {
    return 0;
  }
  int count = 0;
  CornerContacts(grid, pos1, mat1, box_pos, box_rot, size, margin, con, &count);
  PeakContacts(grid, pos1, mat1, BoxFace(box_pos, box_rot, size), margin, con, &count);
  return count;
}

}  // namespace climbsim::sim
