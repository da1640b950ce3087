#include "hmt/area/placement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "hmt/area/online_partitioner.h"
#include "hmt/common/error.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

// Eq. 3 of 003 on a constructed sequence of accumulated errors: with
// E_min = 0.2 and T = 0.5, a place of R = 0.3 (R / T = 0.6) is taken as soon
// as epsilon > E_min / 0.6 = 1/3, and not before; a place of R = 0.6
// (R / T = 1.2) as soon as epsilon > E_min, never at or below it.
TEST(area_Placement, FiresExactlyAsEquation3) {
  const double e_min = 0.2, t = 0.5;
  struct Step {
    double epsilon, r;
    bool fires;
  };
  const Step seq[] = {
      {0.0, 1.0, false},    // not lost
      {0.1, 1.0, false},    // not lost, however distinctive the place
      {0.2, 1.0, false},    // epsilon == E_min: Eq. 3 is strict
      {0.21, 0.6, true},    // 1.2 > 0.2 / 0.21
      {0.21, 0.3, false},   // 0.6 < 0.952
      {0.30, 0.3, false},   // 0.6 < 0.667
      {1.0 / 3.0, 0.3, false},  // 0.6 == 0.6 (strict)
      {0.34, 0.3, true},    // 0.6 > 0.588
      {0.5, 0.2, false},    // 0.4 == 0.4 (strict)
      {0.51, 0.2, true},    // 0.4 > 0.392
      {2.0, 0.05, false},   // 0.1 == 0.1
      {2.0, 0.06, true},    // 0.12 > 0.1
      {2.0, 0.0, false},    // a place with no distinctiveness never
  };
  for (const Step& s : seq)
    EXPECT_EQ(placement_fires(s.epsilon, {s.r}, {t}, e_min), s.fires)
        << "epsilon " << s.epsilon << " R " << s.r;
}

TEST(area_Placement, TakesTheBestModelAndChecksItsArguments) {
  // R_i / T_i: 0.2 / 0.5 = 0.4 and 0.3 / 0.25 = 1.2; the second decides.
  EXPECT_TRUE(placement_fires(0.25, {0.2, 0.3}, {0.5, 0.25}, 0.2));
  EXPECT_FALSE(placement_fires(0.25, {0.2}, {0.5}, 0.2));
  EXPECT_FALSE(placement_fires(1.0, {}, {}, 0.2));
  EXPECT_THROW(placement_fires(1.0, {0.5}, {}, 0.2), std::invalid_argument);
  EXPECT_EQ(parse_placement("both", "area", "placement"), Placement::kBoth);
  EXPECT_THROW(parse_placement("island", "area", "placement"), ConfigError);
}

// A 180-degree, 361-beam scan from the origin, heading +x, inside the box
// |x| <= half_x, |y| <= half_y (returns beyond max_range are invalid).
LaserScan box_scan(double half_x, double half_y, double max_range) {
  LaserScan s;
  s.angle_min = static_cast<float>(-M_PI / 2);
  s.angle_increment = static_cast<float>(M_PI / 360);
  s.max_range = static_cast<float>(max_range);
  for (int i = 0; i < 361; ++i) {
    const double b = s.bearing(i), c = std::cos(b), sn = std::sin(b);
    double r = std::numeric_limits<double>::infinity();
    if (std::fabs(c) > 1e-12) r = std::min(r, half_x / std::fabs(c));
    if (std::fabs(sn) > 1e-12) r = std::min(r, half_y / std::fabs(sn));
    const bool ok = r < max_range;
    s.ranges.push_back(static_cast<float>(ok ? r : max_range));
    s.valid.push_back(ok ? 1 : 0);
  }
  return s;
}

TEST(area_Placement, ScanDistinctivenessPrefersARoomToACorridor) {
  const PlacementOptions o;
  // A corridor constrains the robot across it only: F (the weaker
  // direction) is small. A room's walls constrain both directions.
  const double corridor = scan_distinctiveness(box_scan(100.0, 1.2, 20.0), o);
  const double room = scan_distinctiveness(box_scan(2.5, 2.0, 20.0), o);
  EXPECT_GE(corridor, 0.0);
  EXPECT_LE(room, 1.0);
  EXPECT_LT(corridor, 0.1);
  EXPECT_GT(room, 0.5);
  EXPECT_GT(room, 5.0 * corridor);
  LaserScan none = box_scan(100.0, 100.0, 20.0);
  EXPECT_EQ(scan_distinctiveness(none, o), 0.0);
}

// The partitioner's policies on the simulated three rooms: `both` never
// splits while the robot is not lost and splits exactly as `sso` when Eq. 3
// always fires; `islands` starts an area exactly where Eq. 3 fires.
TEST(area_Placement, PoliciesInThePartitioner) {
  std::vector<Keyframe> kfs = sim::three_rooms_walk();
  AreaOptions o;
  o.partition.tau = 0.7;
  o.partition.split_method = SplitMethod::kSweep;
  const auto events = [&](Placement p, double eps, double r) {
    AreaOptions q = o;
    q.placement.policy = p;
    OnlinePartitioner part(q);
    std::vector<int> at;
    for (Keyframe k : kfs) {
      k.uncertainty = eps;
      k.distinctiveness = r;
      const int id = part.add_keyframe(k);
      if (part.update().new_area) at.push_back(id);
    }
    return at;
  };
  const std::vector<int> sso = events(Placement::kSso, 0.0, 0.0);
  ASSERT_EQ(sso.size(), 2u);
  EXPECT_EQ(events(Placement::kBoth, 1.0, 1.0), sso);
  EXPECT_TRUE(events(Placement::kBoth, 0.1, 1.0).empty());
  EXPECT_TRUE(events(Placement::kIslands, 0.1, 1.0).empty());

  // Islands: epsilon grows by 0.06 per keyframe from the area's start,
  // E_min = 0.15 and R = 0.4 (R / T = 0.8): Eq. 3 fires once epsilon >
  // 0.15 / 0.8 = 0.1875, i.e. at the 4th keyframe after the area's first
  // (0.24; 0.18 at the 3rd does not).
  AreaOptions q = o;
  q.placement.policy = Placement::kIslands;
  q.placement.e_min = 0.15;
  q.placement.threshold = 0.5;
  OnlinePartitioner part(q);
  int since = 0;
  std::vector<int> fired;
  for (size_t i = 0; i < 20; ++i) {
    Keyframe k = kfs[i];
    k.uncertainty = 0.06 * since;
    k.distinctiveness = 0.4;
    const int id = part.add_keyframe(k);
    const std::vector<int> area_before = part.current_area();
    const AreaDecision d = part.update();
    if (d.new_area) {
      fired.push_back(id);
      // The new area holds the newest keyframe; with what stays behind it
      // covers the area left, and it becomes the current area.
      EXPECT_TRUE(std::binary_search(d.new_area_keyframes.begin(), d.new_area_keyframes.end(), id));
      EXPECT_FALSE(d.stay.empty());
      std::vector<int> all = d.stay;
      all.insert(all.end(), d.new_area_keyframes.begin(), d.new_area_keyframes.end());
      std::sort(all.begin(), all.end());
      EXPECT_EQ(all, area_before);
      EXPECT_EQ(part.current_area(), d.new_area_keyframes);
      since = 1;
    } else {
      ++since;
    }
  }
  EXPECT_EQ(fired, (std::vector<int>{4, 8, 12, 16}));
}

}  // namespace
}  // namespace hmt::area
