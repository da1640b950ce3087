#include "hmt/area/online_partitioner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "hmt/area/offline_grouping.h"
#include "hmt/common/config.h"
#include "sim_world.h"

namespace hmt::area {
namespace {

struct OnlineRun {
  std::vector<std::vector<int>> areas;  // in the order they were closed
  std::vector<AreaDecision> events;
};

// Feeds every keyframe, calling update() after each; checks the bookkeeping
// of every new-area event on the way.
OnlineRun run_online(const std::vector<Keyframe>& kfs, const AreaOptions& o) {
  OnlinePartitioner p(o);
  OnlineRun r;
  for (const auto& k : kfs) {
    const std::vector<int> before = p.current_area();
    const int id = p.add_keyframe(k);
    EXPECT_LE(p.window().size(), static_cast<size_t>(o.window_size));
    const AreaDecision d = p.update();
    EXPECT_GE(d.ncut, 0.0);
    EXPECT_LE(d.ncut, 2.0 + 1e-12);
    if (!d.new_area) continue;
    EXPECT_LT(d.ncut, o.partition.tau);
    // The newest keyframe starts the new area; the two sets split the
    // area being left (plus the newest keyframe).
    EXPECT_TRUE(std::binary_search(d.new_area_keyframes.begin(),
                                   d.new_area_keyframes.end(), id));
    std::vector<int> all = d.stay;
    all.insert(all.end(), d.new_area_keyframes.begin(),
               d.new_area_keyframes.end());
    std::sort(all.begin(), all.end());
    std::vector<int> expected = before;
    expected.push_back(id);
    EXPECT_EQ(all, expected);
    EXPECT_GE(d.stay.size(), static_cast<size_t>(o.partition.min_cluster_size));
    EXPECT_GE(d.new_area_keyframes.size(),
              static_cast<size_t>(o.partition.min_cluster_size));
    EXPECT_EQ(p.current_area(), d.new_area_keyframes);
    EXPECT_EQ(p.window(), d.new_area_keyframes);
    r.areas.push_back(d.stay);
    r.events.push_back(d);
  }
  r.areas.push_back(p.current_area());
  return r;
}

std::vector<std::vector<int>> rooms(const std::vector<Keyframe>& kfs) {
  std::vector<std::vector<int>> out(3);
  for (size_t i = 0; i < kfs.size(); ++i)
    out[sim::room_of(kfs[i].pose.mean)].push_back(static_cast<int>(i));
  return out;
}

TEST(area_OnlinePartitioner, AgreesWithOfflineGroupingOnThreeRooms) {
  const auto kfs = sim::three_rooms_walk();
  AreaOptions o;
  o.partition.tau = 0.7;
  o.partition.split_method = SplitMethod::kSweep;
  // Offline, the recursive partition finds the three rooms exactly.
  const Grouping off = group_keyframes(kfs, o);
  ASSERT_EQ(off.groups, rooms(kfs));
  // Online, one new area per door, each decided within two keyframes of
  // where the offline partition puts the boundary.
  const OnlineRun on = run_online(kfs, o);
  ASSERT_EQ(on.areas.size(), off.groups.size());
  for (size_t a = 0; a < on.areas.size(); ++a) {
    const auto& x = on.areas[a];
    const auto& y = off.groups[a];
    EXPECT_TRUE(std::is_sorted(x.begin(), x.end()));
    EXPECT_LE(std::abs(x.front() - y.front()), 2) << "area " << a;
    EXPECT_LE(std::abs(x.back() - y.back()), 2) << "area " << a;
    // Contiguous in time, like the rooms.
    EXPECT_EQ(x.back() - x.front() + 1, static_cast<int>(x.size()));
  }
}

TEST(area_OnlinePartitioner, MeanSplitAlsoFindsOneAreaPerRoom) {
  const auto kfs = sim::three_rooms_walk();
  AreaOptions o;
  o.partition.tau = 0.7;
  const OnlineRun on = run_online(kfs, o);
  const auto r = rooms(kfs);
  ASSERT_EQ(on.areas.size(), 3u);
  for (size_t a = 0; a < 3; ++a) {
    std::vector<int> common;
    std::set_intersection(on.areas[a].begin(), on.areas[a].end(), r[a].begin(),
                          r[a].end(), std::back_inserter(common));
    EXPECT_GE(common.size(), r[a].size() - 4) << "area " << a;
  }
}

TEST(area_OnlinePartitioner, TauZeroNeverSplitsAndTheWindowSlides) {
  const auto kfs = sim::corridor_walk(60.0, 0.5);
  AreaOptions o;
  o.partition.tau = 0.0;
  o.window_size = 40;
  OnlinePartitioner p(o);
  for (const auto& k : kfs) {
    const int id = p.add_keyframe(k);
    const AreaDecision d = p.update();
    EXPECT_FALSE(d.new_area);
    // From three keyframes on, a bisection is still evaluated (one node has
    // nothing to split, two only the Ncut-2 split).
    if (id >= 2) {
      EXPECT_LT(d.ncut, 2.0);
    }
  }
  EXPECT_EQ(p.window().size(), 40u);
  EXPECT_EQ(p.graph().size(), 40u);
  EXPECT_EQ(p.current_area().size(), kfs.size());
  EXPECT_EQ(p.window().front(), static_cast<int>(kfs.size()) - 40);
}

TEST(area_OnlinePartitioner, StayIncludesKeyframesThatLeftTheWindow) {
  // Rooms of ~60 keyframes through a window of 30: the doors are still
  // found, and each event's stay list covers the whole room left behind,
  // including the keyframes that slid out of the window.
  const auto kfs = sim::three_rooms_walk();
  AreaOptions o;
  o.sso.use_probabilistic = false;  // the fixed delta this walk was laid out for
  o.partition.tau_from_sensor = false;
  o.partition.tau = 0.7;
  o.partition.split_method = SplitMethod::kSweep;
  o.window_size = 30;
  const OnlineRun on = run_online(kfs, o);
  ASSERT_EQ(on.areas.size(), 3u);
  const auto r = rooms(kfs);
  size_t total = 0;
  for (size_t a = 0; a < 3; ++a) {
    total += on.areas[a].size();
    EXPECT_GT(on.areas[a].size(), 30u);
    EXPECT_LE(std::abs(on.areas[a].front() - r[a].front()), 2);
    EXPECT_LE(std::abs(on.areas[a].back() - r[a].back()), 2);
  }
  EXPECT_EQ(total, kfs.size());
}

TEST(area_OnlinePartitioner, AKeyframeSensingADisjointPlaceStartsANewArea) {
  const auto kfs = sim::three_rooms_walk();
  AreaOptions o;
  OnlinePartitioner p(o);
  for (int i = 0; i < 20; ++i) {
    p.add_keyframe(kfs[i]);
    EXPECT_FALSE(p.update().new_area);  // a loop in room 1: one area
  }
  // The same scans placed 100 m away: no overlap at all (Ncut 0).
  Keyframe far = kfs[3];
  far.pose.mean = Pose2D(100, 100, 0);
  p.add_keyframe(far);
  const AreaDecision d = p.update();
  ASSERT_TRUE(d.new_area);
  EXPECT_DOUBLE_EQ(d.ncut, 0.0);
  EXPECT_EQ(d.new_area_keyframes, std::vector<int>{20});
  EXPECT_EQ(d.stay.size(), 20u);

  // With min_cluster_size 2 the lone keyframe must wait for a second one.
  o.partition.min_cluster_size = 2;
  OnlinePartitioner q(o);
  for (int i = 0; i < 20; ++i) {
    q.add_keyframe(kfs[i]);
    q.update();
  }
  q.add_keyframe(far);
  EXPECT_FALSE(q.update().new_area);
  Keyframe far2 = kfs[4];
  far2.pose.mean = Pose2D(100.2, 100, 0);
  q.add_keyframe(far2);
  const AreaDecision e = q.update();
  ASSERT_TRUE(e.new_area);
  EXPECT_EQ(e.new_area_keyframes, (std::vector<int>{20, 21}));
}

// Feeds `kfs` with tau 0 (no area event during the walk), then asks for the
// end-of-log decision and checks its bookkeeping.
AreaDecision end_of_walk(const std::vector<Keyframe>& kfs) {
  AreaOptions o;
  o.partition.tau = 0.0;
  OnlinePartitioner p(o);
  for (const auto& k : kfs) {
    p.add_keyframe(k);
    EXPECT_FALSE(p.update().new_area);
  }
  const AreaDecision d = p.end_of_log();
  if (!d.new_area) return d;
  std::vector<int> all = d.stay;
  all.insert(all.end(), d.new_area_keyframes.begin(), d.new_area_keyframes.end());
  std::sort(all.begin(), all.end());
  EXPECT_EQ(all.size(), kfs.size());
  for (size_t i = 0; i < all.size(); ++i) EXPECT_EQ(all[i], static_cast<int>(i));
  EXPECT_EQ(p.current_area(), d.new_area_keyframes);
  EXPECT_EQ(p.window(), d.new_area_keyframes);
  EXPECT_EQ(d.oldest_in_window, d.new_area_keyframes.front());
  return d;
}

TEST(area_OnlinePartitioner, EndOfLogReturnsThePlaceTheWalkEndedIn) {
  // Rooms 1, 2, 3 with no area event on the way: the log's end is in room
  // 3, and that is what end_of_log hands to TSBI, whatever tau says.
  const auto kfs = sim::three_rooms_walk();
  const AreaDecision d = end_of_walk(kfs);
  ASSERT_TRUE(d.new_area);
  EXPECT_EQ(d.new_area_keyframes.back(), static_cast<int>(kfs.size()) - 1);
  size_t in_last_room = 0;
  for (int id : d.new_area_keyframes) {
    EXPECT_NE(sim::room_of(kfs[static_cast<size_t>(id)].pose.mean), 0) << id;
    in_last_room += sim::room_of(kfs[static_cast<size_t>(id)].pose.mean) == 2;
  }
  EXPECT_GE(in_last_room, rooms(kfs)[2].size() - 4);
}

TEST(area_OnlinePartitioner, EndOfLogBackWhereTheAreaBeganIsTheReturnOnly) {
  // Room 1, room 2, then room 1 again: the newest keyframe falls with the
  // oldest, and the place is the return alone (the keyframes after the
  // robot last was in room 2), not the first visit.
  const auto all = sim::three_rooms_walk();
  const auto r = rooms(all);
  std::vector<Keyframe> kfs;
  for (int i : r[0]) kfs.push_back(all[static_cast<size_t>(i)]);
  for (int i : r[1]) kfs.push_back(all[static_cast<size_t>(i)]);
  const int first_return = static_cast<int>(kfs.size());
  for (size_t k = 0; k < 20; ++k) kfs.push_back(all[static_cast<size_t>(r[0][k])]);
  const AreaDecision d = end_of_walk(kfs);
  ASSERT_TRUE(d.new_area);
  ASSERT_FALSE(d.new_area_keyframes.empty());
  EXPECT_GE(d.new_area_keyframes.front(), first_return - 2);
  EXPECT_EQ(d.new_area_keyframes.back(), static_cast<int>(kfs.size()) - 1);
  EXPECT_GE(d.new_area_keyframes.size(), 15u);
}

TEST(area_OnlinePartitioner, EndOfLogWithNothingToSplitIsNoEvent) {
  const auto kfs = sim::three_rooms_walk();
  OnlinePartitioner p{AreaOptions{}};
  EXPECT_FALSE(p.end_of_log().new_area);  // no keyframe
  p.add_keyframe(kfs[0]);
  p.update();
  const AreaDecision d = p.end_of_log();  // one keyframe: nothing to bisect
  EXPECT_FALSE(d.new_area);
  EXPECT_EQ(d.oldest_in_window, 0);
  EXPECT_EQ(p.window(), std::vector<int>{0});
}

TEST(area_OnlinePartitioner, BuiltFromAConfigSection) {
  Config cfg = Config::from_string(
      "[aam]\ntau = 0.7\nsplit_method = sweep\nwindow_size = 500\n", "t.ini");
  AreaOptions o;
  o.load(cfg, "aam");
  EXPECT_NO_THROW(cfg.check_all_used());
  OnlinePartitioner p(o);
  EXPECT_EQ(p.options().window_size, 500);
  EXPECT_EQ(p.keyframe_count(), 0);
  EXPECT_FALSE(p.update().new_area);  // nothing to bisect yet
}

}  // namespace
}  // namespace hmt::area
