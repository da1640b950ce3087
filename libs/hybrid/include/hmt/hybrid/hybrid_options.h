// Options of the hybrid (metric-topological) filter, INI section [hmt], and
// the bundle of every component's options it drives.
#pragma once

#include <string>

#include "hmt/area/area_options.h"
#include "hmt/common/config.h"
#include "hmt/metric_slam/rbpf_options.h"
#include "hmt/tlca/acceptance.h"
#include "hmt/tsbi/tsbi_options.h"

namespace hmt::hybrid {

struct HybridOptions {
  // At most this many topological hypotheses live at once (each runs
  // [metric_slam] particles); the least probable are dropped beyond it.
  int max_hypotheses = 4;
  // Hypotheses less probable than this are dropped.
  double prune_probability = 1e-3;
  // The hypotheses share the [metric_slam] particle budget N as the paper's
  // particles do (each particle carries one topological path): a hypothesis
  // of probability p holds about N p particles, but never fewer than this
  // (so an unlikely topology can still track its pose) nor more than N.
  // 0 gives every hypothesis the full set. With a floor of 10 of 30 (the
  // default), the Infinite Corridor's seeds 1-8 take 25-41 s and 95-144 MB
  // instead of 29-44 s and 99-201 MB, at a position error of 0.73-1.31 m
  // (mean 0.95) instead of 0.66-2.07 m (mean 1.22): rival topologies cost
  // a third of a full set each while they are unlikely. Seeds 1-4 of the
  // other logs: intel 0.062-0.078 m (relations 0.043-0.051 m) against
  // 0.059-0.106 m (0.046-0.050 m) at 57-67 MB against 87 MB, fhw 0.13-0.16
  // against 0.14-0.22 m; csail 0.13-0.28 against 0.13-0.18 m, its dead-end
  // branches turned by 2-3 degrees, their maps as sharp
  // (scripts/map_sharpness.py); the rest alike.
  int min_particles = 10;
  // At a new-area event each hypothesis's weight is also multiplied by the
  // event's evidence, sum over its outcomes of F(gamma) over eta (the
  // optimal proposal's normaliser, 002 Eq. 6, as a Bayes factor against the
  // unexplored area; every hypothesis weighs the same event). Off, the
  // outcomes only share their parent's weight. On, rival topologies that
  // explain the returns equally well no longer live side by side for the
  // rest of the log: on the Infinite Corridor (seeds 1-8) the run takes
  // 22-34 s instead of 21-86 s, but the position error is 0.59-1.95 m
  // against 0.61-1.44 m, so it is an option, not the default.
  bool event_evidence = false;
  // When the log ends, the place it ends in is put to TSBI as a new-area
  // event would put it (OnlinePartitioner::end_of_log), so that a return
  // made inside the log's last area can still close its loop.
  bool end_of_log_event = true;
  // A keyframe for the area abstraction every this much motion.
  double keyframe_distance = 0.5;  // [m]
  double keyframe_angle = 0.5;     // [rad]
  // Floors of an arc's covariance when a new area is entered: a constant
  // and a part proportional to the distance between the two origins (the
  // particles' spread alone is over-confident after resampling).
  double arc_std_xy = 0.05;            // [m]
  double arc_std_theta = 0.02;         // [rad]
  double arc_std_xy_per_metre = 0.01;  // [m/m]
  double arc_std_theta_per_metre = 0.002;  // [rad/m]
  // The heading floor grows with the distance only up to this: a filter
  // that matches its scans against its map keeps the heading it holds,
  // so its heading error does not keep growing with the distance (its 95th
  // percentile over 80-160 m of path is at most 0.092 rad on every shared
  // log). Never below arc_std_theta; 0: no cap.
  double arc_std_theta_max = 0.1;  // [rad]
  // The floors (standard deviations: x and y, heading) of a new arc between
  // two area origins `metres` apart; the position's also stands for the
  // error a keyframe accumulates over `metres` travelled in its area.
  double arc_floor_xy(double metres) const { return arc_std_xy + arc_std_xy_per_metre * metres; }
  double arc_floor_theta(double metres) const;
  // Not an INI key: set by `hmt-slam run --report`. Every TSBI event then
  // keeps what its known-area outcomes were weighed on (TransitionEvent::
  // observed_points, candidate_maps), for the report to draw; off, runs keep
  // no grid alive beyond the hypotheses that hold it.
  bool record_closure_views = false;
  void load(Config& cfg, const std::string& section = "hmt");
};

struct HmtOptions {
  metric_slam::RbpfOptions rbpf;
  area::AreaOptions area;
  tsbi::TsbiOptions tsbi;
  tlca::TlcaOptions tlca;
  HybridOptions hybrid;
};

}  // namespace hmt::hybrid
