// Helpers shared by the reflex tests: scripted sensing and an event log.
#ifndef CLIMBSIM_TESTS_REFLEX_TEST_UTIL_H_
#define CLIMBSIM_TESTS_REFLEX_TEST_UTIL_H_

#include <ostream>
#include <vector>

#include "reflex/reflex.h"

namespace climbsim::reflex {

inline void PrintTo(const LegEvent& event, std::ostream* os) {
  *os << EventName(event.type);
  if (event.reason != LegEventReason::kNone) *os << "(" << ReasonName(event.reason) << ")";
}

namespace testing_util {

// The leg-reflex tests' control period: every duration there is a round number of periods.
inline constexpr double kDt = 0.01;

// Every reflex switched off: a test turns on the one it is about.
inline LegReflexParams AllOff() {
  LegReflexParams p;
  p.preload.enabled = false;
  p.search.enabled = false;
  p.peel.enabled = false;
  p.regrip.enabled = false;
  p.gto.enabled = false;
  p.spindle.enabled = false;
  p.compliance.enabled = false;
  return p;
}

inline LegSensing Swing(double progress = 0.5) {
  LegSensing s;
  s.stance = false;
  s.phase_progress = progress;
  return s;
}

inline LegSensing Stance(double progress = 0.5) {
  LegSensing s;
  s.stance = true;
  s.phase_progress = progress;
  return s;
}

inline LegSensing Touching(LegSensing s) {
  s.touching = true;
  return s;
}

inline LegSensing Attached(LegSensing s, double bonded_fraction = 1.0) {
  s.touching = true;
  s.attached = true;
  s.bonded_fraction = bonded_fraction;
  return s;
}

// An event with the index of the Update that emitted it.
struct TimedEvent {
  int update;
  LegEvent event;
  friend bool operator==(const TimedEvent&, const TimedEvent&) = default;
};

inline void PrintTo(const TimedEvent& e, std::ostream* os) {
  *os << "#" << e.update << " ";
  ::climbsim::reflex::PrintTo(e.event, os);
}

// Runs the leg and logs its events and outputs.
class Recorder {
 public:
  explicit Recorder(LegReflex* leg) : leg_(leg) {}

  const LegReflexOutput& Step(const LegSensing& sensing) {
    outputs_.push_back(leg_->Update(sensing));
    for (const LegEvent& e : outputs_.back().events) {
      events_.push_back({static_cast<int>(outputs_.size()) - 1, e});
    }
    return outputs_.back();
  }
  // Steps `count` times with the same sensing; returns the last output.
  const LegReflexOutput& Repeat(const LegSensing& sensing, int count) {
    for (int i = 0; i < count - 1; ++i) Step(sensing);
    return Step(sensing);
  }

  int updates() const { return static_cast<int>(outputs_.size()); }
  const std::vector<TimedEvent>& events() const { return events_; }
  const LegReflexOutput& output(int update) const { return outputs_.at(update); }

 private:
  LegReflex* leg_;
  std::vector<LegReflexOutput> outputs_;
  std::vector<TimedEvent> events_;
};

inline TimedEvent At(int update, LegEventType type, LegEventReason reason = LegEventReason::kNone) {
  return {update, {type, reason}};
}

}  // namespace testing_util
}  // namespace climbsim::reflex

#endif  // CLIMBSIM_TESTS_REFLEX_TEST_UTIL_H_
