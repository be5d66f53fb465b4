#include "sim/trajectory.h"

#include <charconv>
#include <cmath>

namespace climbsim::sim {

TrajectoryRecorder::TrajectoryRecorder(const World& world, double rate_hz, double duration_s,
                                       const std::vector<const Effect*>& column_sources)
    : sources_(column_sources) {
  const mjModel* m = world.model();
  every_steps_ = std::max(1, static_cast<int>(std::lround(1.0 / (rate_hz * m->opt.timestep))));
  columns_ = {"time_s",  "base_x_m", "base_y_m", "base_z_m",
              "base_qw", "base_qx",  "base_qy",  "base_qz"};
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    joint_qpos_.push_back(m->jnt_qposadr[j]);
    const char* n = mj_id2name(m, mjOBJ_JOINT, j);
    columns_.push_back(std::string(n ? n : "joint" + std::to_string(j)) +
                       (m->jnt_type[j] == mjJNT_HINGE ? "_rad" : "_m"));
  }
  for (const Effect* e : sources_) {
    const size_t before = columns_.size();
    e->TrajectoryColumns(&columns_);
    source_widths_.push_back(static_cast<int>(columns_.size() - before));
  }
  const long steps = std::lround(duration_s / m->opt.timestep);
  capacity_rows_ = static_cast<size_t>(steps / every_steps_ + 2);
  rows_.reserve(capacity_rows_ * columns_.size());
}

void TrajectoryRecorder::Reset(World& world, RunContext&) {
  rows_.clear();
  Record(world);
}

void TrajectoryRecorder::AfterStep(World& world, RunContext& ctx) {
  if ((ctx.step + 1) % every_steps_ == 0) Record(world);
}

void TrajectoryRecorder::Record(const World& world) {
  if (rows_.size() + columns_.size() > capacity_rows_ * columns_.size()) return;
  const mjData* d = world.data();
  const size_t start = rows_.size();
  rows_.resize(start + columns_.size());  // within the reserved capacity: no allocation
  double* row = rows_.data() + start;
  row[0] = d->time;
  const double* root = d->qpos + world.robot().root_qpos_adr;
  for (int i = 0; i < 7; ++i) row[1 + i] = root[i];
  double* out = row + 8;
  for (int adr : joint_qpos_) *out++ = d->qpos[adr];
  for (size_t i = 0; i < sources_.size(); ++i) {
    sources_[i]->TrajectoryValues(world, out);
    out += source_widths_[i];  // each source writes as many values as it declared columns
  }
}

std::string TrajectoryRecorder::ToCsv() const {
  std::string out;
  for (size_t i = 0; i < columns_.size(); ++i) out += (i ? "," : "") + columns_[i];
  out += "\n";
  char buf[32];
  const size_t n = columns_.size();
  for (size_t r = 0; r * n < rows_.size(); ++r) {
    for (size_t c = 0; c < n; ++c) {
      if (c) out += ',';
      // Shortest exact text: a replay or a diff sees the same doubles.
      auto res = std::to_chars(buf, buf + sizeof(buf), rows_[r * n + c]);
      out.append(buf, res.ptr);
    }
    out += '\n';
  }
  return out;
}

}  // namespace climbsim::sim
