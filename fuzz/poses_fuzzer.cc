// The trajectory readers on arbitrary bytes: TUM files (read_tum) and the
// reference pose files of the datasets, 4 or 8 fields (read_pose_file).
#include <cmath>

#include "fuzz_support.h"
#include "hmt/common/error.h"
#include "hmt/grouping/scan_poses.h"
#include "hmt/io/tum.h"

namespace {

void check_poses(const std::vector<hmt::io::StampedPose>& poses) {
  for (const hmt::io::StampedPose& p : poses) {
    hmt::fuzz::check(std::isfinite(p.timestamp), "non-finite pose timestamp");
    hmt::fuzz::check(hmt::fuzz::finite(p.pose), "non-finite pose");
    hmt::fuzz::check(std::abs(p.pose.theta) <= M_PI, "heading outside [-pi, pi]");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static hmt::fuzz::ScratchFile file("poses");
  const std::string& path = file.write(data, size);
  try {
    check_poses(hmt::io::read_tum(path));
  } catch (const hmt::Error&) {
  }
  try {
    check_poses(hmt::grouping::read_pose_file(path));
  } catch (const hmt::Error&) {
  }
  return 0;
}
