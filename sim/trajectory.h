// The trajectory recorder: base pose and joint angles at the scenario's rate, plus columns
// other effects add (bonded fraction of each pad). Rows go into a buffer sized for the whole
// run when it starts, so recording never allocates; the file is written once at the end.
#ifndef CLIMBSIM_SIM_TRAJECTORY_H_
#define CLIMBSIM_SIM_TRAJECTORY_H_

#include <string>
#include <vector>

#include "sim/effect.h"

namespace climbsim::sim {

class TrajectoryRecorder final : public Effect {
 public:
  // Records every `every_steps` steps (the rate rounded to whole steps) and at t = 0.
  TrajectoryRecorder(const World& world, double rate_hz, double duration_s,
                     const std::vector<const Effect*>& column_sources);
  const char* name() const override { return "trajectory"; }
  bool has_after_step() const override { return true; }
  void Reset(World& world, RunContext& ctx) override;
  void AfterStep(World& world, RunContext& ctx) override;

  std::string ToCsv() const;
  const std::vector<std::string>& columns() const { return columns_; }
  int every_steps() const { return every_steps_; }
  // The rows recorded so far, row-major (columns().size() values a row).
  const std::vector<double>& rows() const { return rows_; }

 private:
  void Record(const World& world);

  int every_steps_;
  std::vector<int> joint_qpos_;  // hinge and slide joints, model order
  std::vector<const Effect*> sources_;
  std::vector<int> source_widths_;
  std::vector<std::string> columns_;
  std::vector<double> rows_;      // row-major, capacity for the whole run
  size_t capacity_rows_;
};

}  // namespace climbsim::sim

#endif  // CLIMBSIM_SIM_TRAJECTORY_H_
