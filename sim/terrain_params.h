// The scenario's scene.terrain block: a seeded rough rock surface (a MuJoCo heightfield) in
// place of the plane scenes' flat surface. sim/terrain.h builds it.
#ifndef CLIMBSIM_SIM_TERRAIN_PARAMS_H_
#define CLIMBSIM_SIM_TERRAIN_PARAMS_H_

#include <cmath>
#include <string>
#include <vector>

#include "keys/keys.h"

namespace climbsim::sim {

// Heights h(x, y) about the plane z = 0, a Gaussian random surface with the von Karman
// spectrum C(q) ∝ (1 + (q·ξ)²)^−(1+H): self-affine with Hurst exponent H (rock: 0.5–0.9) at
// wavelengths shorter than the correlation length ξ, flat (rolled off) at longer ones; its
// autocorrelation is R(r) = σ²·2^(1−H)/Γ(H)·(r/ξ)^H·K_H(r/ξ). Sampled on a square grid
// of pitch grid_m, so the shortest wavelength is 2·grid_m.
//
// Defaults (docs/climbing.md, "Rough rock"): the pads are 25 mm squares that bond where their
// face lies within 0.5 mm (adhesion.contact_gap_m) of the rock. ξ = 50 mm, twice the pad, and
// H = 0.8: across one pad the rock rises about σ·√2·(25/50)^0.8 ≈ 0.8σ, most of it a tilt the
// pad's seat follows; what costs contact is the asperities shorter than the pad. σ = 1 mm,
// twice the gap, is rock a pad cannot bridge everywhere: some landings bond half the face.
struct TerrainParams {
  double rms_m = 0.001;
  double correlation_m = 0.05;
  double hurst = 0.8;
  int seed = 1;
  double grid_m = 0.005;
  std::vector<double> extent_m{-0.4, 1.0, -0.4, 0.4};

  template <class A>
  void Serialize(A* a) {
    a->Visit({"rms_m", "m", "RMS height of the rock about the plane z = 0",
              Range::OpenClosed(0, 0.05)},
             &rms_m);
    a->Visit({"correlation_m", "m",
              "correlation length: the spectrum is flat at longer wavelengths (default twice the "
              "pad's side)",
              Range::Closed(0.005, 1)},
             &correlation_m);
    a->Visit({"hurst", "",
              "Hurst exponent of the self-affine range (shorter than the correlation length): "
              "rock 0.5-0.9, larger is smoother",
              Range::Closed(0.5, 0.9)},
             &hurst);
    a->Visit({"seed", "", "draws the rock (independent of the scenario's seed)",
              Range::Closed(0, 2147483647)},
             &seed);
    a->Visit({"grid_m", "m",
              "pitch of the height grid (5 mm: five points across a pad; finer costs collision "
              "time)",
              Range::Closed(0.001, 0.02)},
             &grid_m);
    a->Visit({"extent_m", "m", "area of rock: x_min, x_max, y_min, y_max on the plane z = 0"},
             &extent_m, 4);
  }

  void Validate(const Checker& c) const {
    if (extent_m[1] <= extent_m[0] || extent_m[3] <= extent_m[2]) {
      c.Fail("extent_m", "must be [x_min, x_max, y_min, y_max] with x_min < x_max, y_min < y_max");
    }
    const double n = std::ceil((extent_m[1] - extent_m[0]) / grid_m) *
                     std::ceil((extent_m[3] - extent_m[2]) / grid_m);
    if (n > 4e6) {
      c.Fail("grid_m", "gives " + std::to_string(static_cast<long>(n)) +
                           " heights over extent_m; at most 4000000");
    }
    if (correlation_m < 2 * grid_m) c.Fail("correlation_m", "must be at least 2 * grid_m");
  }
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TERRAIN_PARAMS_H_
