#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/io/tum.h"
#include "text_file.h"

namespace hmt::io {

void write_tum(const std::string& path, const std::vector<StampedPose>& traj) {
  std::string text;
  text.reserve(traj.size() * 96);
  char line[256];
  for (size_t i = 0; i < traj.size(); ++i) {
    const StampedPose& p = traj[i];
    if (!std::isfinite(p.timestamp) || !std::isfinite(p.pose.x) ||
        !std::isfinite(p.pose.y) || !std::isfinite(p.pose.theta))
      throw OutputError("cannot write TUM file '" + path + "': pose " +
                        std::to_string(i) + " is not finite");
    const double half = p.pose.theta / 2.0;
    std::snprintf(line, sizeof(line),
                  "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", p.timestamp,
                  p.pose.x, p.pose.y, 0.0, 0.0, 0.0, std::sin(half),
                  std::cos(half));
    text += line;
  }
  write_text_atomically(path, text);
}

std::vector<StampedPose> read_tum(const std::string& path) {
  const std::string text = detail::read_text_file(path, "TUM file");
  std::vector<StampedPose> out;
  std::vector<std::string_view> f;
  size_t pos = 0, line_no = 0;
  auto fail = [&](const std::string& problem) {
    throw InputError("TUM file '" + path + "' line " +
                     std::to_string(line_no) + ": " + problem);
  };
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    detail::split_fields(std::string_view(text).substr(pos, end - pos), f);
    pos = end + 1;
    if (f.empty() || f[0][0] == '#') continue;
    if (f.size() != 8)
      fail("expected 8 fields (timestamp x y z qx qy qz qw), found " +
           std::to_string(f.size()));
    double v[8];
    for (size_t i = 0; i < 8; ++i) {
      if (!detail::parse_double(f[i], v[i]) || !std::isfinite(v[i]))
        fail("field " + std::to_string(i + 1) + " ('" +
             std::string(f[i].substr(0, 24)) + "') is not a finite number");
    }
    double qx = v[4], qy = v[5], qz = v[6], qw = v[7];
    // Scaled by its largest component first: squares of components near
    // 1e308 would overflow to inf and normalise the rotation away.
    const double big = std::max({std::abs(qx), std::abs(qy), std::abs(qz), std::abs(qw)});
    if (big < 1e-9) fail("the quaternion is zero");
    qx /= big, qy /= big, qz /= big, qw /= big;
    const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
    qx /= norm, qy /= norm, qz /= norm, qw /= norm;
    // Yaw of a general rotation (Z-Y-X convention); for a planar one
    // (qx = qy = 0) this is 2 atan2(qz, qw).
    const double yaw = std::atan2(2.0 * (qw * qz + qx * qy),
                                  1.0 - 2.0 * (qy * qy + qz * qz));
    out.push_back({v[0], Pose2D(v[1], v[2], wrap_angle(yaw))});
  }
  return out;
}

}  // namespace hmt::io
