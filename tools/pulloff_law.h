// climbsim pulloff --law frictional: the directional law (adhesion/frictional_law.h) beside
// the von Mises law on the same pad: the limit curve in the (F_t, F_n) plane and the
// pull-off force against angle, quasi-static on the bond grid and in closed form, written to
// DIR/pulloff.csv, DIR/limit.csv and plotted on one figure, DIR/pulloff.png.
#ifndef CLIMBSIM_TOOLS_PULLOFF_LAW_H_
#define CLIMBSIM_TOOLS_PULLOFF_LAW_H_

#include <string>

#include "adhesion/adhesion.h"

namespace climbsim::tools {

struct PulloffLawOptions {
  std::string out_dir;
  bool force = false;
  bool quiet = false;
  adhesion::PadParams pad;             // the von Mises law's pad (σ_T, μ) and the grid
  adhesion::FrictionalParams law;      // the frictional law (grip direction in the pad frame)
  double arm_m = 0.0;                  // lever of the pull (0: the closed forms apply)
  double from_deg = 0.0, to_deg = 180.0, step_deg = 5.0;
  double max_force_factor = 8.0;
};

// Runs both quasi-static sweeps (along the gripping direction and against it), writes the
// files and prints the table. Plot failures set the exit code 1 (as climbsim pulloff).
void RunPulloffLaws(const PulloffLawOptions& options);

}  // namespace climbsim::tools

#endif  // CLIMBSIM_TOOLS_PULLOFF_LAW_H_
