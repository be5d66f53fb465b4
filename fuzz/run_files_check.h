// What must hold when the run-folder readers read any bytes, shared by fuzz/run_files_fuzzer.cc
// and the replay test fuzz/regression_test.cc. The first byte of an input picks the reader
// (byte % 5; the seeds use the letters A to E), the rest is the file:
//
//   byte % 5   file             reader
//   0 (A)      events.csv       inspect::ReadEvents
//   1 (B)      trajectory.csv   inspect::ReadTrajectory
//   2 (C)      summary.json     inspect::ReadSummary
//   3 (D)      checkpoint.json  optimise::ReadCheckpoint (2 starts of 3 parameters; an input
//                               that is a JSON object gets the fingerprint and checksum it needs,
//                               so that the fuzzer reaches the evaluations behind them)
//   4 (E)      pulloff.csv      inspect::ReadTextCsv
//
// A climbsim::InputError that names the file is fine (bad input: exit code 2); any other
// exception, or an InputError without the file's name, is a finding. Crashes, leaks and
// undefined behaviour stop the fuzzer through the sanitizers.
#ifndef CLIMBSIM_FUZZ_RUN_FILES_CHECK_H_
#define CLIMBSIM_FUZZ_RUN_FILES_CHECK_H_

#include <cstdint>
#include <fstream>
#include <string>

#include "common/common.h"
#include "inspect/inspect.h"
#include "optimise/checkpoint.h"

namespace climbsim::fuzz {

struct RunFileCheck {
  std::string file;  // the file name the input stood for
  bool rejected = false;
  std::string detail;   // the InputError's message when rejected
  std::string finding;  // "" when the reader behaved
};

inline constexpr const char* kRunFileNames[] = {"events.csv", "trajectory.csv", "summary.json",
                                                "checkpoint.json", "pulloff.csv"};
inline constexpr const char* kCheckpointFingerprint = "fuzz";

// A JSON object with "starts" gets the fingerprint and checksum ReadCheckpoint expects.
inline std::string WithValidChecksum(const std::string& text) {
  nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!j.is_object() || !j.contains("starts")) return text;
  j["fingerprint"] = kCheckpointFingerprint;
  j["checksum"] = optimise::CheckpointChecksum(kCheckpointFingerprint, j["starts"]);
  return j.dump();
}

inline void ReadOne(int reader, const std::string& path) {
  switch (reader) {
    case 0:
      inspect::ReadEvents(path);
      break;
    case 1:
      inspect::ReadTrajectory(path);
      break;
    case 2:
      inspect::ReadSummary(path);
      break;
    case 3:
      optimise::ReadCheckpoint(path, kCheckpointFingerprint, 2, 3);
      break;
    default:
      inspect::ReadTextCsv(path);
  }
}

// Writes the input's file into `dir` and reads it with its reader.
inline RunFileCheck CheckRunFileInput(const uint8_t* data, size_t size, const std::string& dir) {
  RunFileCheck c;
  if (size == 0) return c;
  const int reader = data[0] % 5;
  c.file = kRunFileNames[reader];
  std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  if (reader == 3) text = WithValidChecksum(text);
  const std::string path = dir + "/" + c.file;
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  try {
    ReadOne(reader, path);
  } catch (const InputError& e) {
    c.rejected = true;
    c.detail = e.what();
    if (e.file() != path) c.finding = "an InputError that names another file: " + c.detail;
  } catch (const std::exception& e) {
    c.finding = std::string("an exception that is not an InputError: ") + e.what();
  }
  return c;
}

}  // namespace climbsim::fuzz

#endif  // CLIMBSIM_FUZZ_RUN_FILES_CHECK_H_
