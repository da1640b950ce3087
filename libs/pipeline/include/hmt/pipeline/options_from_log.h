// The options whose default is "auto": they follow from the log, and are
// resolved from its first steps before a job starts.
//   [area] tau: from the laser's field of view (hmt/area/area_size.h);
//   [scan_matcher] max_range, and [grid] max_insertion_range with it: from
//   the log's ranges (hmt/metric_slam/matching_range.h).
#pragma once

#include "hmt/pipeline/input_steps.h"
#include "hmt/pipeline/metric_job.h"

namespace hmt::pipeline {

// Resolves the "auto" options of `opt` from the first steps of `steps`,
// which are held until the job takes them: until the range sample is
// complete (at most metric_slam::kRangeSamplePeek steps), or until the first
// scan with a field of view if that comes later (all of them only in a log
// without one). Says
// on stderr what it chose and why.
void resolve_options_from_log(JobOptions& opt, InputSteps& steps);

}  // namespace hmt::pipeline
