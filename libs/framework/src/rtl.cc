#include "hmt/framework/rtl.h"

#include <stdexcept>

namespace hmt::framework {

RealTimeLocalizer::RealTimeLocalizer(const MetricLayer& layer, size_t capacity)
    : layer_(layer), process_("rtl", capacity, [this](Msg& m) { handle(m); }) {}

void RealTimeLocalizer::odometry(uint64_t step, const Pose2D& increment) {
  Msg m;
  m.step = step;
  m.increment = increment;
  process_.post(std::move(m));
}

std::future<RtlPose> RealTimeLocalizer::request() {
  Msg m;
  m.query = true;
  std::future<RtlPose> f = m.reply.get_future();
  if (!process_.post(std::move(m))) {
    std::promise<RtlPose> failed;
    failed.set_exception(std::make_exception_ptr(std::runtime_error("RTL has stopped")));
    return failed.get_future();
  }
  return f;
}

void RealTimeLocalizer::forget_until(uint64_t step) {
  while (!odometry_.empty() && odometry_.front().first <= step) odometry_.pop_front();
}

void RealTimeLocalizer::handle(Msg& m) {
  const MetricEstimate e = layer_.estimate();
  // Odometry metric SLAM has already used is in the estimate.
  if (e.valid) forget_until(e.step);
  if (!m.query) {
    if (!e.valid || m.step > e.step) odometry_.emplace_back(m.step, m.increment);
    return;
  }
  RtlPose p;
  p.valid = e.valid;
  p.estimate_step = e.step;
  p.area = e.area;
  p.pose_in_area = e.pose_in_area;
  p.pose_continuous = e.pose_continuous;
  if (e.valid)
    for (const auto& [step, inc] : odometry_) {
      p.pose_in_area = p.pose_in_area + inc;
      p.pose_continuous = p.pose_continuous + inc;
      ++p.pending_odometry;
    }
  m.reply.set_value(p);
}

}  // namespace hmt::framework
