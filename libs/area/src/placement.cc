#include "hmt/area/placement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hmt/common/error.h"
#include "hmt/common/sensor_data.h"

namespace hmt::area {

Placement parse_placement(const std::string& text, const std::string& section,
                          const std::string& key) {
  if (text == "sso") return Placement::kSso;
  if (text == "islands") return Placement::kIslands;
  if (text == "both") return Placement::kBoth;
  throw ConfigError("[" + section + "] " + key + " = '" + text +
                    "': must be one of sso, islands, both");
}

const char* to_string(Placement p) {
  switch (p) {
    case Placement::kSso:
      return "sso";
    case Placement::kIslands:
      return "islands";
    case Placement::kBoth:
      return "both";
  }
  return "sso";
}

bool placement_fires(double epsilon, const std::vector<double>& r,
                     const std::vector<double>& t, double e_min) {
  if (r.size() != t.size())
    throw std::invalid_argument("placement_fires: one threshold per model type");
  // First line of Eq. 3: the robot is not lost yet.
  if (!(epsilon > e_min)) return false;
  double best = -1.0;
  for (size_t i = 0; i < r.size(); ++i) best = std::max(best, r[i] / t[i]);
  // Second line: the best normalised R beats E_min / epsilon, which falls
  // below 1 as the error grows (the more lost, the less demanding).
  return !r.empty() && best > e_min / epsilon;
}

namespace {

struct Hit {
  double x = 0.0, y = 0.0;  // sensor frame
  double range = 0.0;
  double vx = 1.0, vy = 0.0;  // unit viewing direction
};

struct Influence {
  double ux = 1.0, uy = 0.0;  // axis (sign irrelevant)
  double magnitude = 0.0;
};

// Eq. 11.
double sigmoid(double value, double cutoff, double rate) {
  if (!(value > 0.0)) return 0.0;
  const double cm = std::pow(value, rate);
  return cm / (std::pow(cutoff, rate) + cm);
}

// Normal (minor principal axis) and isotropy l2 / l1 of the hits within
// `radius` of hit i; neighbours are searched outward along the scan until a
// hit lies beyond the radius (returns of one surface are consecutive beams).
void normal_at(const std::vector<Hit>& hits, size_t i, double radius, double& nx, double& ny,
               double& isotropy) {
  const double r2 = radius * radius;
  std::vector<size_t> nb{i};
  for (size_t j = i + 1; j < hits.size(); ++j) {
    const double dx = hits[j].x - hits[i].x, dy = hits[j].y - hits[i].y;
    if (dx * dx + dy * dy > r2) break;
    nb.push_back(j);
  }
  for (size_t j = i; j-- > 0;) {
    const double dx = hits[j].x - hits[i].x, dy = hits[j].y - hits[i].y;
    if (dx * dx + dy * dy > r2) break;
    nb.push_back(j);
  }
  nx = -hits[i].vx;  // an isolated hit faces the viewer
  ny = -hits[i].vy;
  isotropy = 1.0;
  if (nb.size() < 2) return;
  double mx = 0.0, my = 0.0;
  for (size_t j : nb) mx += hits[j].x, my += hits[j].y;
  mx /= nb.size();
  my /= nb.size();
  double cxx = 0.0, cxy = 0.0, cyy = 0.0;
  for (size_t j : nb) {
    const double dx = hits[j].x - mx, dy = hits[j].y - my;
    cxx += dx * dx, cxy += dx * dy, cyy += dy * dy;
  }
  const double tr = cxx + cyy, det = cxx * cyy - cxy * cxy;
  const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
  const double l1 = 0.5 * tr + disc, l2 = std::max(0.0, 0.5 * tr - disc);
  if (!(l1 > 0.0)) return;
  isotropy = l2 / l1;
  // Major axis angle; the normal is perpendicular to it.
  const double major = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);
  nx = -std::sin(major);
  ny = std::cos(major);
}

}  // namespace

double scan_distinctiveness(const LaserScan& scan, const PlacementOptions& o) {
  std::vector<Hit> hits;
  for (size_t i = 0; i < scan.size(); ++i) {
    const double r = scan.ranges[i];
    if (!(i < scan.valid.size() && scan.valid[i]) || !(r > 0.0) || r > o.max_range) continue;
    Hit h;
    const double b = scan.bearing(i);
    h.vx = std::cos(b);
    h.vy = std::sin(b);
    h.x = r * h.vx;
    h.y = r * h.vy;
    h.range = r;
    hits.push_back(h);
  }
  if (hits.size() < 2) return 0.0;
  const double dtheta = std::fabs(scan.angle_increment);
  std::vector<Influence> inf;
  inf.reserve(2 * hits.size());
  for (size_t i = 0; i < hits.size(); ++i) {
    double nx, ny, iso;
    normal_at(hits, i, o.normal_radius, nx, ny, iso);
    const double w = std::exp(-o.decay * hits[i].range) * dtheta;  // Eq. 8
    const double facing = std::fabs(nx * hits[i].vx + ny * hits[i].vy);
    if (iso < 1.0) inf.push_back({nx, ny, (1.0 - iso) * w * facing});       // Eq. 7
    if (iso > 0.0) inf.push_back({hits[i].vx, hits[i].vy, iso * w});
  }
  // Reference vector: the axis window (mod pi) holding the most influence,
  // its direction their weighted mean axis (angles doubled).
  const double window = o.reference_window * M_PI / 180.0;
  std::vector<double> axis(inf.size());
  for (size_t i = 0; i < inf.size(); ++i) {
    double a = std::atan2(inf[i].uy, inf[i].ux);
    if (a < 0.0) a += M_PI;
    if (a >= M_PI) a -= M_PI;
    axis[i] = a;
  }
  double best = -1.0, ref = 0.0;
  for (size_t i = 0; i < inf.size(); ++i) {
    double sum = 0.0, c2 = 0.0, s2 = 0.0;
    for (size_t j = 0; j < inf.size(); ++j) {
      double d = axis[j] - axis[i];
      if (d < 0.0) d += M_PI;
      if (d > window) continue;
      sum += inf[j].magnitude;
      c2 += inf[j].magnitude * std::cos(2.0 * axis[j]);
      s2 += inf[j].magnitude * std::sin(2.0 * axis[j]);
    }
    if (sum > best) best = sum, ref = 0.5 * std::atan2(s2, c2);
  }
  const double rx = std::cos(ref), ry = std::sin(ref);
  double par = 0.0, perp = 0.0;  // Eq. 9-10
  for (const Influence& v : inf) {
    par += v.magnitude * std::fabs(rx * v.ux + ry * v.uy);
    perp += v.magnitude * std::fabs(rx * v.uy - ry * v.ux);
  }
  const double sp = sigmoid(par, o.cutoff, o.rate), sq = sigmoid(perp, o.cutoff, o.rate);
  const double hi = std::max(sp, sq), lo = std::min(sp, sq);
  const double q = hi > 0.0 ? lo / hi : 0.0;  // Eq. 12
  return lo * (1.0 + q) * 0.5;                // F = min (Eq. 5)
}

}  // namespace hmt::area
