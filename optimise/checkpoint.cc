// DIR/checkpoint.json and the JSON of evaluations (optimise/checkpoint.h).
#include "optimise/checkpoint.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string_view>

#include "common/common.h"

namespace climbsim::optimise {
namespace {

namespace fs = std::filesystem;

// A count: a JSON integer in [0, INT_MAX]. get<int> casts whatever number it finds (1e300 is
// undefined behaviour, 2^40 wraps), so the range is checked here.
int CountFromJson(const nlohmann::json& n) {
  if (!n.is_number_unsigned() || n.get<uint64_t>() > std::numeric_limits<int>::max()) {
    throw std::invalid_argument("expected a whole number >= 0, got " + n.dump());
  }
  return static_cast<int>(n.get<uint64_t>());
}

}  // namespace

uint64_t Fnv1a(std::string_view s) {
  // A digit short of FNV's offset basis since the first checkpoints: kept, so that their
  // checksums, fingerprints and the starts' seeds stay what they were.
  return common::Fnv1a64(s, 1469598103934665603ull);
}

// Checksum of a checkpoint: FNV-1a of the fingerprint (scenario and budget) and the
// canonical dump of the evaluations, as hex.
std::string CheckpointChecksum(const std::string& fingerprint, const nlohmann::json& starts) {
  char buf[17];
  std::snprintf(buf, sizeof(buf), "%016llx",
                static_cast<unsigned long long>(Fnv1a(fingerprint + "|" + starts.dump())));
  return buf;
}

nlohmann::json CostToJson(const Cost& c) {
  return {{"total", c.total},
          {"speed_mps", c.speed_mps},
          {"fall_penalty", c.fall_penalty},
          {"overload_penalty", c.overload_penalty},
          {"energy_penalty", c.energy_penalty},
          {"failed", c.failed},
          {"failure", c.failure},
          {"early_stop", c.early_stop},
          {"stop_time_s", c.stop_time_s},
          {"wall_time_s", c.wall_time_s},
          {"stable", c.stable},
          {"fell", c.fell},
          {"fall_time_s", c.fall_time_s},
          {"distance_m", c.distance_m}};
}

Cost CostFromJson(const nlohmann::json& n) {
  Cost c;
  c.total = n.at("total").get<double>();
  c.speed_mps = n.at("speed_mps").get<double>();
  c.fall_penalty = n.at("fall_penalty").get<double>();
  c.overload_penalty = n.at("overload_penalty").get<double>();
  c.energy_penalty = n.at("energy_penalty").get<double>();
  c.failed = n.at("failed").get<bool>();
  c.failure = n.at("failure").get<std::string>();
  // Absent from checkpoints written before early stopping.
  c.early_stop = n.value("early_stop", std::string());
  c.stop_time_s = n.value("stop_time_s", 0.0);
  c.wall_time_s = n.value("wall_time_s", 0.0);
  // Absent from checkpoints written before the robustness term.
  c.stable = n.value("stable", true);
  c.fell = n.value("fell", false);
  c.fall_time_s = n.value("fall_time_s", -1.0);
  c.distance_m = n.value("distance_m", 0.0);
  return c;
}

nlohmann::json ToJson(const Evaluation& e) {
  return {{"x", e.x},
          {"objective", e.objective},
          {"nominal", CostToJson(e.nominal)},
          {"failed_runs", e.failed_runs},
          {"wall_time_s", e.wall_time_s},
          {"cases_failed", e.cases_failed},
          {"robustness_penalty", e.robustness_penalty}};
}

Evaluation FromJson(const nlohmann::json& j, int start, int index) {
  Evaluation e;
  e.start = start;
  e.index = index;
  e.x = j.at("x").get<std::vector<double>>();
  e.objective = j.at("objective").get<double>();
  e.nominal = CostFromJson(j.at("nominal"));
  e.failed_runs = CountFromJson(j.at("failed_runs"));
  e.wall_time_s = j.at("wall_time_s").get<double>();
  e.cases_failed = j.contains("cases_failed") ? CountFromJson(j["cases_failed"]) : 0;
  e.robustness_penalty = j.value("robustness_penalty", 0.0);
  return e;
}

// Reads DIR/checkpoint.json for --resume: every value of the right type, the scenario's
// fingerprint, and the checksum of the content (accidental damage is refused; an edit with
// the checksum recomputed passes here, and the optimiser's recheck of a replayed best keeps it
// out of the result).
std::vector<std::vector<Evaluation>> ReadCheckpoint(const std::string& path,
                                                    const std::string& fingerprint, int starts,
                                                    size_t dimension) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError(path, 0, 0, "",
                     "missing: nothing to resume (drop --resume to start over, with --force)");
  }
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    const size_t byte = std::min<size_t>(e.byte, text.size());
    const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + byte, '\n'));
    throw InputError(path, line, 0, "", std::string("unreadable: ") + e.what());
  } catch (const std::exception& e) {  // a number out of range
    throw InputError(path, 0, 0, "", std::string("unreadable: ") + e.what());
  }
  if (!j.is_object() || !j.contains("fingerprint") || !j["fingerprint"].is_string() ||
      !j.contains("checksum") || !j["checksum"].is_string() || !j.contains("starts") ||
      !j["starts"].is_array()) {
    throw InputError(path, 0, 0, "",
                     "not a climbsim checkpoint (expected an object with fingerprint, checksum "
                     "and starts)");
  }
  if (j["fingerprint"].get<std::string>() != fingerprint) {
    throw InputError(path, 0, 0, "fingerprint",
                     "belongs to another scenario or budget; drop --resume (and use --force) "
                     "to start over");
  }
  if (j["checksum"].get<std::string>() != CheckpointChecksum(fingerprint, j["starts"])) {
    throw InputError(path, 0, 0, "checksum",
                     "does not match the content: the checkpoint was edited or damaged; drop "
                     "--resume (and use --force) to start over");
  }
  std::vector<std::vector<Evaluation>> recorded(starts);
  const auto& list = j["starts"];
  for (int s = 0; s < starts && s < static_cast<int>(list.size()); ++s) {
    if (!list[s].is_array()) throw InputError(path, 0, 0, "starts", "expected lists");
    for (size_t i = 0; i < list[s].size(); ++i) {
      const std::string where = "starts[" + std::to_string(s) + "][" + std::to_string(i) + "]";
      try {
        recorded[s].push_back(FromJson(list[s][i], s, static_cast<int>(i)));
      } catch (const std::exception& e) {  // a missing key, a wrong type, a count out of range
        throw InputError(path, 0, 0, where, std::string("wrong value: ") + e.what());
      }
      if (recorded[s].back().x.size() != dimension) {
        throw InputError(path, 0, 0, where + ".x",
                         "expected " + std::to_string(dimension) + " parameters");
      }
    }
  }
  return recorded;
}

}  // namespace climbsim::optimise
