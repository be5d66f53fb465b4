// The ranges of the numeric options of `climbsim optimise` and `climbsim pulloff`, declared
// once: the command line checks them (tools/) and the Python binding checks its arguments of
// the same meaning against them (python/).
#ifndef CLIMBSIM_EXPERIMENTS_OPTION_RANGES_H_
#define CLIMBSIM_EXPERIMENTS_OPTION_RANGES_H_

#include <string>

#include "common/common.h"
#include "scenario/archive.h"

namespace climbsim::optimise {

// [lo, hi], in the option's type (CLI11 words its help by the type: INT or FLOAT).
template <class T>
struct OptionRange {
  T lo;
  T hi;
};

// climbsim optimise
inline constexpr OptionRange<int> kThreadsRange{0, 1024};
inline constexpr OptionRange<int> kMaxEvaluationsRange{1, 100000000};

// climbsim pulloff: the pad, the rig and the sweep
inline constexpr OptionRange<double> kPadWidthRangeM{1e-4, 1.0};  // --width-m, --length-m
inline constexpr OptionRange<int> kGridRange{1, 1024};            // --grid, --grid-x, --grid-y
inline constexpr OptionRange<double> kSigmaTRangePa{1e-3, 1e12};
inline constexpr OptionRange<double> kMuRange{0.0, 1e3};
inline constexpr OptionRange<int> kMinBondsRange{1, 1 << 20};
inline constexpr OptionRange<double> kArmRangeM{0.0, 1.0};
inline constexpr OptionRange<double> kAzimuthRangeDeg{-360.0, 360.0};  // --azimuth-deg, --grip-deg
inline constexpr OptionRange<double> kPullAngleRangeDeg{0.0, 180.0};   // --from-deg, --to-deg
inline constexpr OptionRange<double> kStepRangeDeg{0.01, 180.0};
inline constexpr OptionRange<double> kRampTimeRangeS{1e-3, 1e3};
inline constexpr OptionRange<double> kTimestepRangeS{1e-5, 0.01};
inline constexpr OptionRange<double> kGainRangeN{0.0, 1e9};
inline constexpr OptionRange<double> kFrictionRange{1e-3, 10.0};
inline constexpr OptionRange<double> kMaxForceFactorRange{1.01, 1e3};
inline constexpr OptionRange<double> kCriticalAngleRangeDeg{0.01, 89.99};
inline constexpr OptionRange<double> kShearLimitRangePa{1e-3, 1e12};
inline constexpr OptionRange<double> kFrictionMuRange{0.0, 1e3};

// Throws InputError(where, key) unless v is in the range ("must be in [lo, hi], got v").
template <class T>
void CheckInRange(const char* where, const char* key, double v, const OptionRange<T>& range) {
  const double lo = static_cast<double>(range.lo), hi = static_cast<double>(range.hi);
  if (!(v >= lo && v <= hi)) {
    throw InputError(where, 0, 0, key,
                     "must be in [" + sim::ExactNumber(lo) + ", " + sim::ExactNumber(hi) +
                         "], got " + sim::ExactNumber(v));
  }
}

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_EXPERIMENTS_OPTION_RANGES_H_
