// The per-pad event log behind DIR/events.csv. Rows are held in a buffer reserved when the
// run starts; adding one never allocates. If a run produces more events than were reserved
// the extra rows are counted, not stored, and summary.json says how many were dropped.
#ifndef CLIMBSIM_SIM_EVENTS_H_
#define CLIMBSIM_SIM_EVENTS_H_

#include <mujoco/mujoco.h>

#include <array>
#include <string>
#include <vector>

namespace climbsim::sim {

// One row. `kind` and `cause` point at string literals (no allocation in the step).
struct Event {
  double time_s = 0.0;
  int pad = -1;                  // index into EventLog::pad_names()
  const char* kind = "";         // touchdown, attach, attach_rejected, bonds_lost, detach, ...
  const char* cause = "";        // the failed condition or detach cause, "" when none
  double cause_value = 0.0;      // written as cause=value when has_cause_value
  bool has_cause_value = false;
  int surface_geom = -1;         // geom touched, -1 when none
  double bonded_fraction = 0.0;
  std::array<double, 5> load{};  // fn_n, fx_n, fy_n, mx_nm, my_nm in the pad frame
};

class EventLog {
 public:
  static constexpr const char* kHeader =
      "time_s,pad,event,cause,surface,bonded_fraction,fn_n,fx_n,fy_n,mx_nm,my_nm";

  EventLog() = default;
  // Names of the pads (pad body names), and how many rows to reserve.
  void Configure(std::vector<std::string> pad_names, size_t capacity);
  void Clear() { rows_.clear(), dropped_ = 0; }

  void Add(const Event& e) {
    if (rows_.size() < rows_.capacity()) {
      rows_.push_back(e);
    } else {
      ++dropped_;
    }
  }

  const std::vector<Event>& rows() const { return rows_; }
  const std::vector<std::string>& pad_names() const { return pad_names_; }
  long dropped() const { return dropped_; }

  // The whole file, header included; surface names come from the model.
  std::string ToCsv(const mjModel* model) const;

 private:
  std::vector<std::string> pad_names_;
  std::vector<Event> rows_;
  long dropped_ = 0;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_EVENTS_H_
