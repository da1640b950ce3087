// hmt_consumer LOG: reads a log with hmt_io and loads the built-in default
// configuration with hmt_pipeline, from an installed HMT-SLAM.
#include <cstdio>
#include <exception>

#include "hmt/common/config.h"
#include "hmt/io/log_reader.h"
#include "hmt/pipeline/default_config.h"
#include "hmt/pipeline/metric_job.h"
#include "hmt/version.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: hmt_consumer LOG\n");
    return 2;
  }
  try {
    const hmt::Log log = hmt::io::read_log(argv[1]);
    hmt::Config cfg = hmt::pipeline::layered_config({}, {"metric_slam.particles=12"});
    const hmt::pipeline::JobOptions opt = hmt::pipeline::load_job_options(cfg, "");
    std::printf("%s\n", hmt::version_string("hmt_consumer").c_str());
    std::printf("scans: %zu\n", log.steps.size());
    std::printf("first range: %.2f\n", log.steps.empty() ? 0.0 : log.steps[0].scan.ranges[0]);
    std::printf("particles: %d\n", opt.rbpf.particles);
    std::printf("resolution: %.3f\n", opt.rbpf.resolution);
    std::printf("default config: %zu bytes\n", hmt::pipeline::default_config_text().size());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hmt_consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
