// Checkpoints: the whole state of an HMT-SLAM run between two scans, saved
// so that `hmt-slam resume --checkpoint FILE` continues the run exactly as
// if it had never stopped (deterministic mode: the final outputs are the
// same bytes).
//
// What is saved: every member of the estimation (framework::HmtSystem and
// what it owns: the hybrid filter's hypotheses with every particle's pose,
// path, weights and map, the random streams, the area abstraction's graph,
// the stored areas, arcs, pending closures, the records the outputs are
// written from), plus what identifies the run: the program's version, the
// effective configuration, the input log and a fingerprint of the steps
// processed. Caches that do not change results (TSBI's match fields and
// cost stacks) are rebuilt on demand. Tiles and maps that particles and
// hypotheses share copy-on-write are saved once and shared again on load, so
// a resumed run holds the memory the original did.
//
// File layout (little-endian):
//   0  char[8] magic "HMTCKPT\x1a"
//   8  u32     format version (kCheckpointFormatVersion)
//  12  u32     flags (0)
//  16  u64     payload size
//  24  u32     CRC-32 of the payload
//  28  u32     CRC-32 of bytes 0..27
//  32  payload: a cereal binary archive of the identity, then the state.
// The format follows the in-memory types, so a checkpoint is read only by the
// same version of hmt-slam (the version is checked, and the format version
// is raised whenever a saved type changes). Written with
// write_file_atomically: a kill at any moment leaves the previous checkpoint
// or the new one, never a partial file.
#pragma once

#include <cstdint>
#include <string>

#include "hmt/common/sensor_data.h"
#include "hmt/framework/hmt_system.h"

namespace hmt::checkpoint {

constexpr uint32_t kCheckpointFormatVersion = 10;
constexpr size_t kCheckpointHeaderSize = 32;
inline constexpr char kCheckpointMagic[8] = {'H', 'M', 'T', 'C', 'K', 'P', 'T', '\x1a'};

// Which run a checkpoint belongs to and how far it got.
struct RunIdentity {
  std::string version;  // HMT_VERSION of the program that wrote it
  std::string config;   // the effective configuration (config_effective.ini)
  std::string input;    // the log, as the run was given it
  uint64_t steps = 0;   // log steps processed
  uint32_t log_crc = 0; // log_fingerprint() of those steps
  bool report = false;  // run with --report (the closure views it records)
};

// A fingerprint of log steps, chained step by step from 0: resume checks
// that the log it is given starts with the steps the checkpoint processed.
uint32_t log_fingerprint(uint32_t crc, const LogStep& step);

// Writes the identity (its version set to this program's) and the system's
// state; to be called on its metric SLAM thread
// (HmtSystem::run_between_steps) in deterministic mode. Throws OutputError
// if the file cannot be written (an earlier checkpoint at `path` stays).
void save(const std::string& path, const RunIdentity& identity,
          const framework::HmtSystem& system);

// Checks the file (magic, format version, sizes, both checksums, the
// program's version) and returns its identity. Throws InputError naming the
// file and the problem.
RunIdentity read_identity(const std::string& path);

// Restores the state saved in `path` into a system constructed with the
// checkpoint's configuration, before its start(), and returns its identity.
// Throws InputError if the file is not a valid checkpoint.
RunIdentity load(const std::string& path, framework::HmtSystem& system);

}  // namespace hmt::checkpoint
