// The CARMEN text log reader (gzip or plain) on arbitrary bytes.
#include <cmath>

#include "fuzz_support.h"
#include "hmt/common/error.h"
#include "hmt/io/carmen.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static hmt::fuzz::ScratchFile file("carmen");
  const std::string& path = file.write(data, size);
  try {
    std::vector<hmt::Pose2D> odometry;
    const hmt::Log log = hmt::io::read_carmen(path, &odometry);
    hmt::fuzz::check_log(log);
    hmt::fuzz::check(odometry.size() == log.steps.size(), "one odometry pose per step");
    for (const hmt::Pose2D& p : odometry)
      hmt::fuzz::check(hmt::fuzz::finite(p), "non-finite odometry pose");
  } catch (const hmt::Error&) {
  }
  return 0;
}
