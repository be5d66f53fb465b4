#include "sim/events.h"

#include <cstdio>

namespace climbsim::sim {

void EventLog::Configure(std::vector<std::string> pad_names, size_t capacity) {
  pad_names_ = std::move(pad_names);
  rows_.clear();
  rows_.reserve(capacity);
  dropped_ = 0;
}

std::string EventLog::ToCsv(const mjModel* m) const {
  std::string out = std::string(kHeader) + "\n";
  char buf[512];
  for (const Event& e : rows_) {
    const char* pad = e.pad >= 0 && e.pad < static_cast<int>(pad_names_.size())
                          ? pad_names_[e.pad].c_str()
                          : "";
    const char* surface = "";
    if (e.surface_geom >= 0 && m != nullptr) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, e.surface_geom);
      surface = name != nullptr ? name : "";
    }
    char cause[96];
    if (e.has_cause_value) {
      std::snprintf(cause, sizeof(cause), "%s=%.6g", e.cause, e.cause_value);
    } else {
      std::snprintf(cause, sizeof(cause), "%s", e.cause);
    }
    std::snprintf(buf, sizeof(buf), "%.6f,%s,%s,%s,%s,%.6f,%.9g,%.9g,%.9g,%.9g,%.9g\n", e.time_s,
                  pad, e.kind, cause, surface, e.bonded_fraction, e.load[0], e.load[1],
                  e.load[2], e.load[3], e.load[4]);
    out += buf;
  }
  return out;
}

}  // namespace climbsim::sim
