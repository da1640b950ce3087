// Saving and loading the topological layer: an HMT map (areas with their
// frames, keyframes and archived local maps; arcs) and the topological
// hypotheses, in one versioned binary file that loads back exactly (every
// double, float and cell bit for bit).
//
// File layout, version 2 (all integers little-endian, IEEE-754 floats
// stored as their bit patterns, little-endian):
//
//   header, 40 bytes
//     0  char[8]  magic "HMTTOPO\x1a"
//     8  u32      format version (kTopologyFormatVersion)
//    12  u32      flags (0)
//    16  u64      payload size, inflated
//    24  u64      stored size: bytes of the zlib stream that follows
//    32  u32      CRC-32 of the inflated payload
//    36  u32      CRC-32 of header bytes 0..35
//   zlib stream (deflate), exactly `stored size` bytes, then end of file.
//
//   payload
//     u32 area count, then per area (ascending id):
//       u32 id; u32 frame.parent (0xffffffff = none); f64 x, y, theta of
//       frame.origin_in_parent; u64 created_step; f64 created_time
//       u32 keyframe count, then per keyframe: f64 x, y, theta;
//         u64 step (0xffffffffffffffff = not known); f64 timestamp;
//         f32 angle_min, angle_increment, max_range;
//         f64 sensor x, y, theta; u32 beams; f32 ranges[beams];
//         u8 valid[beams]
//       u8 has_map; if 1: f64 resolution; u32 tile count; then per
//         allocated tile (ascending ty, then tx): i32 tx, ty (tile
//         coordinates, cell >> kTileBits) and its 1024 cells as four planes
//         in the tile's cell order: logodds[1024], hits[1024], hx[1024],
//         hy[1024] (planes compress better than interleaved cells)
//     u32 arc count, then per arc (ascending (from, to), from < to):
//       u32 from, to; f64 x, y, theta; f64 cov[9] (row-major);
//       u32 measurements
//     u32 hypothesis count, then per hypothesis (in order):
//       f64 log_weight; u32 path length; per entry u32 area, u64 step
//
// Only allocated tiles are stored, and the whole payload is deflated (free
// and unknown space is highly repetitive). Reading checks the magic, the
// version, both checksums and sizes, then every invariant the in-memory types
// keep (ids ascending and unique, arcs between existing areas with positive
// definite covariances, valid hypothesis paths); any failure is an
// hmt::InputError naming the file and the problem. Writing goes through
// write_file_atomically: a failed save never leaves a partial file.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hmt/topology/closure_record.h"
#include "hmt/topology/hmt_map.h"
#include "hmt/topology/hypotheses.h"

namespace hmt::topology {

// Version 1 files (keyframes without their steps) are read too: every
// keyframe's step is then kUnknownStep.
constexpr uint32_t kTopologyFormatVersion = 2;
constexpr uint32_t kOldestTopologyFormatVersion = 1;
constexpr size_t kTopologyHeaderSize = 40;
inline constexpr char kTopologyMagic[8] = {'H', 'M', 'T', 'T',
                                           'O', 'P', 'O', '\x1a'};

struct TopologySnapshot {
  HmtMap map;
  std::vector<TopologicalHypothesis> hypotheses;
};

// The file's bytes. Throws std::invalid_argument if a hypothesis is invalid
// or names an area the map does not have.
std::string encode_topology(
    const HmtMap& map, const std::vector<TopologicalHypothesis>& hypotheses);
// Parses the file's bytes; `origin` names them in error messages. Throws
// InputError.
TopologySnapshot decode_topology(const std::string& bytes,
                                 const std::string& origin);

// Atomic write; throws OutputError if the file cannot be written (and
// std::invalid_argument as encode_topology).
void save_topology(const std::string& path, const HmtMap& map,
                   const std::vector<TopologicalHypothesis>& hypotheses);
// Throws InputError for a missing, unreadable, truncated or corrupt file.
TopologySnapshot load_topology(const std::string& path);

// The HMT map file of a run (hmt_map.bin): every live hypothesis with its
// own map and path, and what is needed to continue the run from where it
// stopped (hmt-slam resume). Same header layout as above, with magic
// "HMTSESS\x1a" and its own version; payload (version 5):
//   u64 steps processed; f64 timestamp of the last one;
//   u32 map count, then each distinct area map once, as a map is stored
//     above (f64 resolution; u32 tile count; tiles): hypotheses share the
//     maps of the areas they left before they branched, so a run with
//     several hypotheses does not store (or hold while writing) each
//     shared map once per hypothesis;
//   u32 hypothesis count, then per hypothesis (ascending id):
//     u32 id; f64 x, y, theta of the robot in its current area (the best
//     particle); f64 x, y, theta of that area's frame in the area
//     abstraction's frame; a topology payload as above with this
//     hypothesis's map and its one path (log_weight = its log
//     probability), except that each area's has_map byte and map are
//     replaced by a u32 index into the map table (0xffffffff: no map);
//     then its loop closures not yet accepted: u32 count, per closure
//     u32 from, to; u64 step; f64 x, y, theta, cov[9] of the measurement;
//     u8 has_arc_before, and if 1 that arc as stored above;
//   u32 count, then the area abstraction's graph (the keyframes it holds
//     when the run stops, oldest first), each as an area's keyframe
//     (pose in the area abstraction's frame, scan).
// Version 2 files (without the closures and the graph), version 3 files
// (without the graph) and version 4 files (keyframes without their steps,
// as topology format 1) are read too: no pending closures, an empty graph,
// steps kUnknownStep. Every part is checked as a topology file is, each
// hypothesis's current area must have a map, and a closure must join two
// distinct areas of its hypothesis's map. Files are deflated as they are
// encoded, so writing one holds the compressed file, not the whole payload.
constexpr uint32_t kSessionFormatVersion = 5;
constexpr uint32_t kOldestSessionFormatVersion = 2;
inline constexpr char kSessionMagic[8] = {'H', 'M', 'T', 'S', 'E', 'S', 'S', '\x1a'};

struct SessionHypothesis {
  uint32_t id = 0;
  HmtMap map;
  TopologicalHypothesis topo;
  Pose2D robot;
  Pose2D aam_from_area;
  std::vector<ClosureRecord> pending_closures;
};

struct Session {
  uint64_t steps = 0;
  double time = 0.0;
  std::vector<SessionHypothesis> hypotheses;
  // The area abstraction's keyframe graph (its window), poses in its frame.
  std::vector<Keyframe> area_graph;
};

std::string encode_session(const Session& session);
Session decode_session(const std::string& bytes, const std::string& origin);
void save_session(const std::string& path, const Session& session);
Session load_session(const std::string& path);

}  // namespace hmt::topology
