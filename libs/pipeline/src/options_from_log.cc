#include "hmt/pipeline/options_from_log.h"

#include <cstdio>

#include "hmt/area/area_size.h"
#include "hmt/metric_slam/matching_range.h"

namespace hmt::pipeline {

void resolve_options_from_log(JobOptions& opt, InputSteps& steps) {
  bool tau_open = opt.area.partition.tau_from_sensor;
  metric_slam::RangeSample ranges;
  bool ranges_open = opt.rbpf.matcher.range_from_scans;
  for (size_t k = 0; tau_open || ranges_open; ++k) {
    const LogStep* s = steps.peek(k);
    if (!s) break;
    if (tau_open && area::resolve_tau(opt.area, s->scan)) {
      tau_open = false;
      std::fprintf(stderr, "hmt-slam: [area] tau = auto: %.3f from the laser's field of view\n",
                   opt.area.partition.tau);
    }
    if (ranges_open) {
      ranges.add(s->scan, s->odometry_increment);
      ranges_open = !ranges.complete();
    }
  }
  if (metric_slam::resolve_matching_range(opt.rbpf.matcher, opt.rbpf.insertion, ranges))
    std::fprintf(stderr,
                 "hmt-slam: [scan_matcher] max_range = auto: %.0f m (%.0f %% of the %zu returns "
                 "of %zu scans a metre apart, the first %zu of the log, lie within %.1f m; at least "
                 "%.0f m)\n",
                 opt.rbpf.matcher.max_range, 100.0 * metric_slam::kMatchingRangeQuantile,
                 ranges.returns(), ranges.scans(), ranges.read(), ranges.quantile(),
                 metric_slam::kMinMatchingRange);
}

}  // namespace hmt::pipeline
