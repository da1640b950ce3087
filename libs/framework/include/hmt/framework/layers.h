// The three data layers of 002 Sec. V as the processes share them.
//
// Ownership first: the particles, the keyframe graph and the hypotheses'
// maps are each owned by one process (metric SLAM owns the hybrid filter,
// the area abstraction owns the partitioner) and reach the others only as
// immutable snapshots inside messages (copy-on-write maps). What must be read
// while its owner runs is published here, one writer per layer, behind the
// layer's mutex; readers get a consistent copy. That is all other threads
// (RTL, the progress line, the output writers) ever touch.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <vector>

#include "hmt/common/pose2d.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::framework {

// Local metric layer: the latest estimate of metric SLAM.
struct MetricEstimate {
  bool valid = false;       // false until the first step is processed
  uint64_t step = 0;        // the last step processed
  double time = 0.0;        // its log timestamp
  topology::AreaId area = topology::kNoArea;
  Pose2D pose_in_area;      // its best particle's estimate, in the most probable hypothesis
  Pose2D pose_continuous;   // the same pose in the area abstraction's frame
  double ess = 0.0;         // of the most probable hypothesis
  size_t hypotheses = 0;
};

struct MetricBusy {
  bool busy = false;   // a step is being processed
  uint64_t step = 0;   // which
  double for_ms = 0.0; // since when
};

// Written by the metric SLAM process only.
class MetricLayer {
 public:
  void begin_step(uint64_t step);
  void end_step(const MetricEstimate& estimate);
  MetricEstimate estimate() const;
  MetricBusy busy() const;

 private:
  mutable std::mutex mutex_;  // guards every member below
  MetricEstimate estimate_;
  bool busy_ = false;
  uint64_t busy_step_ = 0;
  std::chrono::steady_clock::time_point busy_since_;
};

// Area layer: what the area abstraction has decided so far.
struct AreaSummary {
  size_t keyframes = 0;           // keyframes in the graph's history
  size_t new_area_decisions = 0;  // "robot entered a new area" events
  uint64_t last_decision_step = 0;
};

// Written by the area abstraction process only.
class AreaLayer {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  void record_keyframe(uint64_t step, bool new_area);
  AreaSummary summary() const;

 private:
  mutable std::mutex mutex_;  // guards summary_
  AreaSummary summary_;
};

// Topological layer: the hypotheses about the HMT map.
struct HypothesisSummary {
  uint32_t id = 0;
  double probability = 0.0;
  topology::AreaId area = topology::kNoArea;  // current area
  size_t areas = 0;                           // in its map
};

struct TopologySummary {
  std::vector<HypothesisSummary> hypotheses;  // ascending id
  std::map<topology::AreaId, double> pmf;     // 002 Eq. 14
  size_t transitions = 0;                     // TSBI evaluations applied
  size_t closures_accepted = 0;               // by TLCA
  size_t best_areas = 0;                      // areas of the most probable hypothesis
};

// Written by the metric SLAM process (which applies TSBI's and TLCA's
// results to the hypotheses it owns).
class TopologicalLayer {
 public:
  void publish(TopologySummary summary);
  TopologySummary summary() const;

 private:
  mutable std::mutex mutex_;  // guards summary_
  TopologySummary summary_;
};

}  // namespace hmt::framework
