#include "hmt/grouping/scan_poses.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <numeric>
#include <sstream>

#include "hmt/common/error.h"
#include "hmt/common/files.h"

namespace hmt::grouping {
namespace {

size_t scans_considered(const Log& log, size_t n) {
  return (n == 0 || n > log.steps.size()) ? log.steps.size() : n;
}

// Whole file, decompressed if gzip (zlib reads plain files as they are).
std::string read_maybe_gzip(const std::string& path, const std::string& what) {
  require_readable_file(path, what);
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw InputError("cannot open " + what + " '" + path + "'");
  std::string text;
  char buf[1 << 16];
  while (true) {
    const int got = gzread(f, buf, sizeof buf);
    if (got < 0) {
      int err = 0;
      const std::string msg = gzerror(f, &err);
      gzclose(f);
      throw InputError(what + " '" + path + "' is damaged: " + msg);
    }
    if (got == 0) break;
    text.append(buf, static_cast<size_t>(got));
  }
  gzclose(f);
  return text;
}

std::vector<std::string> fields_of(const std::string& line) {
  std::istringstream is(line);
  std::vector<std::string> f;
  std::string w;
  while (is >> w) f.push_back(w);
  return f;
}

bool parse_finite(const std::string& s, double* v) {
  errno = 0;
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && errno != ERANGE &&
         std::isfinite(*v);
}

}  // namespace

ScanPoses odometry_poses(const Log& log, size_t n) {
  n = scans_considered(log, n);
  ScanPoses out;
  out.source = "odometry";
  out.pose.resize(n);
  out.has_pose.assign(n, 1);
  Pose2D p;
  for (size_t i = 0; i < n; ++i) {
    if (i > 0 && log.steps[i].has_odometry) p = p + log.steps[i].odometry_increment;
    out.pose[i] = p;
  }
  return out;
}

std::vector<io::StampedPose> read_pose_file(const std::string& path) {
  const std::string what = "trajectory file";
  const std::string text = read_maybe_gzip(path, what);
  // Find the field count of the first data line.
  std::istringstream in(text);
  std::string line;
  size_t line_no = 0, expected = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto f = fields_of(line);
    if (f.empty() || f[0][0] == '#') continue;
    expected = f.size();
    break;
  }
  if (expected == 0) throw InputError(what + " '" + path + "' holds no pose");
  if (expected == 8) return io::read_tum(path);
  if (expected != 4)
    throw InputError(what + " '" + path + "' line " + std::to_string(line_no) +
                     ": expected 4 fields (timestamp x y theta) or 8 (TUM: "
                     "timestamp x y z qx qy qz qw), found " +
                     std::to_string(expected));
  std::vector<io::StampedPose> out;
  in.clear();
  in.seekg(0);
  line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const auto f = fields_of(line);
    if (f.empty() || f[0][0] == '#') continue;
    const std::string where =
        what + " '" + path + "' line " + std::to_string(line_no) + ": ";
    if (f.size() != 4)
      throw InputError(where + "expected 4 fields (timestamp x y theta), found " +
                       std::to_string(f.size()));
    double v[4];
    for (int k = 0; k < 4; ++k)
      if (!parse_finite(f[k], &v[k]))
        throw InputError(where + "field " + std::to_string(k + 1) + " ('" +
                         f[k].substr(0, 24) + "') is not a finite number");
    out.push_back({v[0], Pose2D(v[1], v[2], wrap_angle(v[3]))});
  }
  return out;
}

ScanPoses match_poses(const Log& log, const std::vector<io::StampedPose>& traj,
                      double tolerance, const std::string& traj_name,
                      size_t n) {
  n = scans_considered(log, n);
  ScanPoses out;
  out.source = traj_name;
  out.pose.resize(n);
  out.has_pose.assign(n, 0);
  // Poses by timestamp (stable: equal stamps keep the file order).
  std::vector<size_t> order(traj.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return traj[a].timestamp < traj[b].timestamp;
  });
  for (size_t i = 0; i < n; ++i) {
    const double t = log.steps[i].timestamp;
    auto it = std::lower_bound(
        order.begin(), order.end(), t,
        [&](size_t k, double v) { return traj[k].timestamp < v; });
    // Candidates: the last pose before t and the first at or after it.
    size_t best = traj.size();
    double best_dt = tolerance;
    if (it != order.begin()) {
      const size_t k = *(it - 1);
      const double dt = t - traj[k].timestamp;
      if (dt <= best_dt) best = k, best_dt = dt;
    }
    if (it != order.end()) {
      const size_t k = *it;
      const double dt = traj[k].timestamp - t;
      if (dt < best_dt || (best == traj.size() && dt <= best_dt)) best = k;
    }
    if (best < traj.size()) {
      out.pose[i] = traj[best].pose;
      out.has_pose[i] = 1;
    } else {
      ++out.missing;
    }
  }
  if (n > 0 && out.missing == n)
    throw InputError("no scan of '" + log.source + "' has a pose in '" +
                     traj_name + "' within " + std::to_string(tolerance) +
                     " s of its timestamp: the trajectory belongs to another log");
  return out;
}

}  // namespace hmt::grouping
