// climbsim fit-adhesion: a pad law's parameters from a lab's pull-off measurements. The
// prediction of every measurement is the quasi-static pull-off of adhesion/pulloff.h on the
// bond grid the simulations use (the same search, the same cascade, each row's pad size,
// lever and direction), and the fit is a bounded least squares over the law's parameters
// with NLopt: a global search (GN_DIRECT_L) over the parameters that are not a strength
// scale, the scale solved in closed form (every law's pull-off is proportional to its
// strength), then a local polish of all of them (LN_BOBYQA). docs/calibrate-adhesion.md is
// the user's page.
#ifndef CLIMBSIM_EXPERIMENTS_FIT_ADHESION_H_
#define CLIMBSIM_EXPERIMENTS_FIT_ADHESION_H_

#include <functional>
#include <string>
#include <vector>

#include "adhesion/adhesion.h"

namespace climbsim::optimise {

// One measured pull-off (a CSV row). Angles in the pad frame of adhesion/pulloff.h.
struct PulloffMeasurement {
  double angle_from_normal_deg = 0.0;  // 0 pulls straight off, 90 shears
  double azimuth_deg = 0.0;            // in-plane part, from pad +x towards +y
  double force_n = 0.0;                // measured pull-off
  double width_m = 0.0, length_m = 0.0;
  double arm_m = 0.0;                  // lever: pull point above the pad face
  double preload_n = 0.0;              // recorded; the quasi-static rig starts fully bonded
  int repeat = 0;
  int line = 0;                        // in the file, for messages
};

struct PulloffData {
  std::string file;
  std::vector<PulloffMeasurement> rows;
  bool has_azimuth = false;
  bool has_repeat = false;
};

// Reads DATA.csv (header: angle_from_normal_deg, force_n, and any of azimuth_deg,
// pad_width_m, pad_length_m, lever_arm_m, preload_n, repeat). Pad size columns may be left
// out when width_m/length_m (> 0) are given. Throws InputError(file, line, column, column name)
// for anything else: an unknown or bare `angle` column, a missing cell, a number out of range.
PulloffData ReadPulloffCsv(const std::string& path, double width_m = 0.0, double length_m = 0.0);

// The law's parameters as fitted.
struct FittedParameter {
  std::string key;      // adhesion.<key> (e.g. sigma_t_pa, frictional.critical_angle_deg)
  std::string unit;
  double value = 0.0;
  double uncertainty = 0.0;  // one standard uncertainty; NaN when the data cannot say
  double low95 = 0.0, high95 = 0.0;  // the interval that the fit reports at 95 %
  bool fitted = true;        // false: held at its default (the data cannot identify it)
};

struct FitAdhesionOptions {
  std::string law = "von_mises";  // von_mises | frictional | tabulated
  int grid = 16;                  // bonds per side of the predictions' grid
  double grip_deg = 0.0;          // frictional: the gripping direction's azimuth in the data
  double assumed_spread = 0.05;   // relative measurement spread when the data has no repeats
  int max_evaluations = 3000;     // NLopt, per stage
  std::function<void(const std::string&)> progress{};  // a line now and then (may be empty)
};

struct AdhesionFit {
  std::string law;
  std::vector<FittedParameter> parameters;
  std::vector<double> predicted_n;  // one per row
  double rms_n = 0.0, worst_n = 0.0;
  int worst_row = 0;                // index into rows
  double spread_n = 0.0;            // measurement spread the verdict compares with
  bool spread_from_repeats = false;
  bool represents = true;           // false: "this law cannot represent your data"
  std::string verdict;              // one line
  int evaluations = 0;              // predictions of the whole table
  adhesion::PadParams von_mises;    // the fitted laws, ready for a scenario
  adhesion::FrictionalParams frictional;
  adhesion::TabulatedParams tabulated;
};

// Throws InputError when `law` is not known or cannot take the data (tabulated: angles over
// 90 deg), naming the row.
void CheckFitData(const PulloffData& data, const std::string& law);

// The fit (see the file comment). Throws InputError for a law that the data cannot be fitted
// with (tabulated with an angle over 90 deg, a law name not known).
AdhesionFit FitAdhesion(const PulloffData& data, const FitAdhesionOptions& options);

// The pull-off each law predicts for one row (the same search the fit uses); 0 for a pad that
// holds at no force, the search's cap for one that never lets go.
double PredictPulloff(const AdhesionFit& fit, const PulloffMeasurement& row, int grid);

// The `adhesion:` block for a scenario (fitted.yaml's text).
std::string FittedYaml(const AdhesionFit& fit, const PulloffData& data);

struct FitAdhesionRunOptions {
  std::string data_file;
  std::string out_dir;
  bool force = false, keep_other_files = false, quiet = false;
  double width_m = 0.0, length_m = 0.0;  // when the CSV has no pad size columns
  FitAdhesionOptions fit;
};

// climbsim fit-adhesion: reads, fits the chosen law and the two others (for the plot),
// writes DIR/{parameters.csv, residuals.csv, curves.csv, fit.gp, fit.png, fitted.yaml,
// verdict.txt} and prints the verdict. Returns false when only the plot is missing.
bool RunFitAdhesion(const FitAdhesionRunOptions& options);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_EXPERIMENTS_FIT_ADHESION_H_
