// The HTML report of `hmt-slam run --report`: OUT/report/index.html, a
// static page (plain JS and CSS, no server, works from file://) that steps
// through the run: the map with the trajectory up to the step and the areas
// created so far, P(current area) and the ESS over time with a cursor at the
// step, and every new-area event at which a known area was a candidate, each
// candidate drawn both ways (the new observations over the area's grid at
// TSBI's best match, the loop closure, and at the pose the arcs predict, what
// "a new area" amounts to).
//
// Files, all under OUT/report/ and linked by relative paths:
//   index.html, report.js, report.css   the page (embedded in the binary
//                                       from libs/pipeline/report/)
//   data.js                             the run: `window.HMT_REPORT = {...}`
//                                       (a script, not JSON: file:// pages
//                                       may not fetch files)
//   closures/area_<id>_<k>.png          each candidate area's grid as TSBI
//                                       weighed it (k-th distinct version;
//                                       an earlier run's others are removed)
// The map itself is ../map.png. The same run gives the same bytes; every
// file is written atomically.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hmt/framework/hmt_system.h"
#include "hmt/global_map/global_poses.h"
#include "hmt/grid/map_export.h"
#include "hmt/hybrid/hybrid_filter.h"
#include "hmt/topology/hmt_map.h"

namespace hmt::pipeline {

class ReportWriter {
 public:
  // `out_dir`: the run's output folder; the report goes to out_dir/report.
  explicit ReportWriter(std::string out_dir);
  ~ReportWriter();
  ReportWriter(const ReportWriter&) = delete;
  ReportWriter& operator=(const ReportWriter&) = delete;

  // What the filter did, taken while it still exists: the per-step PMF and
  // ESS, the TSBI events (their candidate grids are drawn now, into
  // closures/, so the filter's maps can be released) and the accepted
  // closures. The events need HybridOptions::record_closure_views to carry
  // their views; without it the events are listed but not drawn.
  void add_filter(const std::vector<framework::StepTrace>& traces,
                  const std::vector<hybrid::TransitionEvent>& events,
                  const std::vector<hybrid::AcceptanceEvent>& acceptances);

  // The final estimate: where map.png lies (`frame`), one global pose per
  // step from `first_step`, the area each step was in (the path's
  // segments), and the areas' global poses and arcs.
  void add_map(const grid::MapFrame& frame, const std::vector<Pose2D>& trajectory,
               uint64_t first_step, const std::vector<hybrid::TrajectorySegment>& segments,
               const topology::HmtMap& map, const global_map::GlobalPoses& poses);

  // Writes data.js and the page; returns the path of index.html. `summary`
  // is summary.json's text (shown as the run's totals).
  std::string write(const std::string& summary_json);

 private:
  struct Data;
  std::string dir_;
  std::unique_ptr<Data> data_;
};

}  // namespace hmt::pipeline
