// DIR/checkpoint.json of `climbsim optimise`, and the JSON of its evaluations (also what MPI
// ranks exchange):
//
//   {"fingerprint": "<scenario and budget>", "checksum": "<16 hex digits>",
//    "starts": [[{"x": [...], "objective": J, "nominal": {cost}, "failed_runs": n,
//                 "wall_time_s": t}, ...], ...]}
//
// The checksum is FNV-1a of the fingerprint and the canonical dump of "starts": an edited
// number is refused, not trusted. Header of its own so that fuzz/ reads it without NLopt.
#ifndef CLIMBSIM_OPTIMISE_CHECKPOINT_H_
#define CLIMBSIM_OPTIMISE_CHECKPOINT_H_

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "optimise/optimise.h"

namespace climbsim::optimise {

// FNV-1a, 64 bits: the checksum's hash (the run's fingerprint and start seeds use it too).
uint64_t Fnv1a(std::string_view s);

nlohmann::json CostToJson(const Cost& c);
// Throws nlohmann::json::exception for a missing key or a value of the wrong type.
Cost CostFromJson(const nlohmann::json& n);
nlohmann::json ToJson(const Evaluation& e);
// As CostFromJson, and std::invalid_argument for failed_runs outside [0, INT_MAX]; `start`
// and `index` are the evaluation's place (not in the JSON).
Evaluation FromJson(const nlohmann::json& j, int start, int index);

// The checksum of a checkpoint's "starts" under `fingerprint`, 16 hex digits.
std::string CheckpointChecksum(const std::string& fingerprint, const nlohmann::json& starts);

// Reads a checkpoint for --resume: the evaluations of the first `starts` starts, each with
// `dimension` parameters. Throws InputError (path, line, key) for a missing or unreadable
// file, another scenario's fingerprint, a checksum that does not match, or a wrong value.
std::vector<std::vector<Evaluation>> ReadCheckpoint(const std::string& path,
                                                    const std::string& fingerprint, int starts,
                                                    size_t dimension);

}  // namespace climbsim::optimise

#endif  // CLIMBSIM_OPTIMISE_CHECKPOINT_H_
