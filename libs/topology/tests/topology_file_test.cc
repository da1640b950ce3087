#include "hmt/topology/topology_file.h"

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <utility>

#include "hmt/common/error.h"
#include "hmt/common/random.h"
#include "hmt_test/scratch.h"

namespace hmt::topology {
namespace {
namespace fs = std::filesystem;

// ------------------------------------------------------------ fixtures

// The test's folder, removed if the test passes.
class TempDir {
 public:
  TempDir() {
    path_ = scratch::folder(std::string("topology_") +
                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
  }
  std::string file(const std::string& name) const {
    return (path_ / name).string();
  }

 private:
  fs::path path_;
};

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// Every field of some cells in several tiles, negative coordinates included.
grid::OccupancyGrid random_grid(double resolution, Random& rng) {
  grid::OccupancyGrid g(resolution);
  for (int i = 0; i < 3000; ++i) {
    const grid::CellIndex at{static_cast<int>(rng.uniform(-90, 70)),
                             static_cast<int>(rng.uniform(-40, 100))};
    grid::Cell c;
    c.logodds = static_cast<int8_t>(rng.uniform(-127, 127));
    c.hits = static_cast<uint8_t>(rng.uniform(0, 255));
    c.hx = static_cast<int8_t>(rng.uniform(-127, 127));
    c.hy = static_cast<int8_t>(rng.uniform(-127, 127));
    g.set_cell(at, c);
  }
  return g;
}

Keyframe random_keyframe(Random& rng, int beams) {
  Keyframe k;
  k.pose = Pose2D(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-3, 3));
  k.scan.timestamp = 1.6e9 + rng.uniform(0, 100);
  k.scan.angle_min = static_cast<float>(-M_PI / 2);
  k.scan.angle_increment = static_cast<float>(M_PI / (beams - 1));
  k.scan.max_range = 30.0f;
  k.scan.sensor_pose = Pose2D(0.2, 0.0, 0.01);
  for (int i = 0; i < beams; ++i) {
    k.scan.ranges.push_back(static_cast<float>(rng.uniform(0.1, 30)));
    k.scan.valid.push_back(rng.uniform() < 0.9 ? 1 : 0);
  }
  k.scan.ranges[0] = std::numeric_limits<float>::quiet_NaN();
  k.scan.ranges[1] = std::numeric_limits<float>::infinity();
  k.step = static_cast<uint64_t>(rng.uniform(0, 1e6));
  return k;
}

Eigen::Matrix3d correlated(double s) {
  Eigen::Matrix3d c;
  c << 0.04, 0.01, 0.002,  //
      0.01, 0.09, -0.003,  //
      0.002, -0.003, 0.0025;
  return s * c;
}

struct Fixture {
  HmtMap map;
  std::vector<TopologicalHypothesis> hypotheses;
};

Fixture sample_topology() {
  Random rng(99);
  Fixture f;
  HmtMap& m = f.map;
  m.add_area(0, {kNoArea, Pose2D(), 0, 100.0});
  m.add_area(1, {0, Pose2D(4.5, -0.5, 0.7), 140, 114.0});
  m.add_area(2, {1, Pose2D(3.0, 2.0, -2.9), 260, 126.0});
  m.add_area(7, {0, Pose2D(-3.0, 1.0, 3.1), 400, 140.0});
  for (int i = 0; i < 3; ++i) m.add_keyframe(0, random_keyframe(rng, 181));
  m.add_keyframe(1, random_keyframe(rng, 361));
  Keyframe unknown = random_keyframe(rng, 2);
  unknown.step = kUnknownStep;  // as read from an older file
  m.add_keyframe(7, unknown);
  grid::OccupancyGrid g0 = random_grid(0.05, rng);
  grid::OccupancyGrid g1 = g0;  // shares g0's tiles in memory ...
  for (int i = 0; i < 50; ++i)  // ... except where it is changed
    g1.mutable_logodds({static_cast<int>(rng.uniform(-20, 20)), 5}) = 77;
  m.archive_map(0, g0);
  m.archive_map(1, g1);
  m.archive_map(7, grid::OccupancyGrid(0.1));  // archived, but empty
  // Area 2 is the current area: no archived map.
  m.add_arc_measurement(0, 1,
                        PoseGaussian(Pose2D(4.5, -0.5, 0.7), correlated(1)));
  m.add_arc_measurement(
      1, 0, inverse(PoseGaussian(Pose2D(4.4, -0.4, 0.72), correlated(2))));
  m.add_arc_measurement(2, 1,
                        PoseGaussian(Pose2D(-1, 3, 3.0), correlated(0.5)));
  m.add_arc_measurement(0, 7, PoseGaussian(Pose2D(-3, 1, 3.1), correlated(3)));

  TopologicalHypothesis a, b, c;
  for (auto* h : {&a, &b, &c}) {
    enter_area(*h, 0, 0);
    enter_area(*h, 1, 140);
  }
  enter_area(a, 2, 260);
  enter_area(b, 7, 260);
  enter_area(c, 2, 261);
  a.log_weight = -1.5;
  b.log_weight = -std::numeric_limits<double>::infinity();
  c.log_weight = -1234.25;
  f.hypotheses = {a, b, c};
  return f;
}

// ------------------------------------------------------------ comparison

uint64_t bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
uint32_t bits(float v) {
  uint32_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
void expect_same_pose(const Pose2D& a, const Pose2D& b) {
  EXPECT_EQ(bits(a.x), bits(b.x));
  EXPECT_EQ(bits(a.y), bits(b.y));
  EXPECT_EQ(bits(a.theta), bits(b.theta));
}

void expect_same_grid(const grid::OccupancyGrid& a,
                      const grid::OccupancyGrid& b) {
  EXPECT_EQ(bits(a.resolution()), bits(b.resolution()));
  EXPECT_EQ(a.tile_count(), b.tile_count());
  grid::CellIndex alo, ahi, blo, bhi;
  const bool any = a.bounds(&alo, &ahi);
  ASSERT_EQ(any, b.bounds(&blo, &bhi));
  if (!any) return;
  ASSERT_EQ(alo.x, blo.x);
  ASSERT_EQ(alo.y, blo.y);
  ASSERT_EQ(ahi.x, bhi.x);
  ASSERT_EQ(ahi.y, bhi.y);
  size_t cells = 0, differing = 0;
  for (int y = alo.y; y <= ahi.y; ++y)
    for (int x = alo.x; x <= ahi.x; ++x) {
      if (a.known({x, y}) != b.known({x, y})) {
        ++differing;
        continue;
      }
      if (!a.known({x, y})) continue;
      const grid::Cell ca = a.cell({x, y}), cb = b.cell({x, y});
      ++cells;
      if (ca.logodds != cb.logodds || ca.hits != cb.hits ||
          ca.hx != cb.hx || ca.hy != cb.hy)
        ++differing;
    }
  EXPECT_EQ(differing, 0u);
  EXPECT_EQ(cells, a.tile_count() * grid::kTileSize * grid::kTileSize);
}

void expect_same_keyframes(const std::vector<Keyframe>& a, const std::vector<Keyframe>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    const LaserScan& sa = a[k].scan;
    const LaserScan& sb = b[k].scan;
    expect_same_pose(a[k].pose, b[k].pose);
    EXPECT_EQ(a[k].step, b[k].step);
    EXPECT_EQ(bits(sa.timestamp), bits(sb.timestamp));
    EXPECT_EQ(bits(sa.angle_min), bits(sb.angle_min));
    EXPECT_EQ(bits(sa.angle_increment), bits(sb.angle_increment));
    EXPECT_EQ(bits(sa.max_range), bits(sb.max_range));
    expect_same_pose(sa.sensor_pose, sb.sensor_pose);
    ASSERT_EQ(sa.ranges.size(), sb.ranges.size());
    for (size_t i = 0; i < sa.ranges.size(); ++i)
      EXPECT_EQ(bits(sa.ranges[i]), bits(sb.ranges[i]));
    EXPECT_EQ(sa.valid, sb.valid);
  }
}

void expect_same(const TopologySnapshot& got, const Fixture& want) {
  ASSERT_EQ(got.map.area_ids(), want.map.area_ids());
  for (AreaId id : want.map.area_ids()) {
    SCOPED_TRACE("area " + std::to_string(id));
    const Area& a = got.map.area(id);
    const Area& b = want.map.area(id);
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.frame.parent, b.frame.parent);
    expect_same_pose(a.frame.origin_in_parent, b.frame.origin_in_parent);
    EXPECT_EQ(a.frame.created_step, b.frame.created_step);
    EXPECT_EQ(bits(a.frame.created_time), bits(b.frame.created_time));
    expect_same_keyframes(a.keyframes, b.keyframes);
    ASSERT_EQ(a.map != nullptr, b.map != nullptr);
    if (a.map) expect_same_grid(*a.map, *b.map);
  }
  ASSERT_EQ(got.map.arcs().size(), want.map.arcs().size());
  for (const auto& kv : want.map.arcs()) {
    const Arc* a = got.map.find_arc(kv.first.first, kv.first.second);
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->from, kv.second.from);
    EXPECT_EQ(a->to, kv.second.to);
    EXPECT_EQ(a->measurements, kv.second.measurements);
    expect_same_pose(a->pose.mean, kv.second.pose.mean);
    for (int i = 0; i < 9; ++i)
      EXPECT_EQ(bits(a->pose.cov.data()[i]),
                bits(kv.second.pose.cov.data()[i]));
  }
  ASSERT_EQ(got.hypotheses.size(), want.hypotheses.size());
  for (size_t i = 0; i < got.hypotheses.size(); ++i) {
    EXPECT_EQ(got.hypotheses[i].path, want.hypotheses[i].path);
    EXPECT_EQ(bits(got.hypotheses[i].log_weight),
              bits(want.hypotheses[i].log_weight));
  }
}

// ------------------------------------------------------------ container

void put_u32(std::string& s, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_u64(std::string& s, uint64_t v) {
  for (int i = 0; i < 8; ++i)
    s.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void put_f64(std::string& s, double v) { put_u64(s, bits(v)); }
void put_f32(std::string& s, float v) {
  uint32_t b;
  std::memcpy(&b, &v, 4);
  put_u32(s, b);
}

// A topology payload's start: one area, id 0, the root (frame and creation
// all zero), up to its count of `keyframes`.
std::string one_root_area(uint32_t keyframes) {
  std::string s;
  put_u32(s, 1);            // one area
  put_u32(s, 0);            // id
  put_u32(s, 0xffffffffu);  // no parent
  for (int i = 0; i < 3; ++i) put_f64(s, 0.0);
  put_u64(s, 0);  // created step
  put_f64(s, 0.0);  // created time
  put_u32(s, keyframes);
  return s;
}

// A keyframe in the documented layout: pose (1, 2, 0.5), step 42 when
// `with_step` (topology format 2, session format 5), a two-beam scan.
void append_keyframe(std::string& s, bool with_step) {
  for (double v : {1.0, 2.0, 0.5}) put_f64(s, v);
  if (with_step) put_u64(s, 42);
  put_f64(s, 3.0);  // timestamp
  for (float v : {-1.5f, 3.0f, 10.0f}) put_f32(s, v);  // angle_min, increment, max_range
  for (int i = 0; i < 3; ++i) put_f64(s, 0.0);          // sensor pose
  put_u32(s, 2);
  put_f32(s, 1.0f);
  put_f32(s, 2.0f);
  s.push_back(1);
  s.push_back(1);
}
uint32_t crc(const std::string& s, size_t n) {
  return static_cast<uint32_t>(crc32(
      0L, reinterpret_cast<const Bytef*>(s.data()), static_cast<uInt>(n)));
}

// The payload of a file (inflated), and a file around a payload, written
// here from the layout documented in topology_file.h.
std::string unwrap(const std::string& file) {
  uint64_t size = 0;
  for (int i = 0; i < 8; ++i)
    size |= static_cast<uint64_t>(static_cast<uint8_t>(file[16 + i]))
            << (8 * i);
  std::string payload(size, '\0');
  uLongf n = size;
  EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(payload.data()), &n,
                       reinterpret_cast<const Bytef*>(file.data() + 40),
                       file.size() - 40),
            Z_OK);
  return payload;
}
std::string wrap(const std::string& payload, const char (&magic)[8] = kTopologyMagic,
                 uint32_t version = kTopologyFormatVersion) {
  uLongf n = compressBound(payload.size());
  std::string z(n, '\0');
  EXPECT_EQ(
      compress(reinterpret_cast<Bytef*>(z.data()), &n,
               reinterpret_cast<const Bytef*>(payload.data()), payload.size()),
      Z_OK);
  z.resize(n);
  std::string h(magic, 8);
  put_u32(h, version);
  put_u32(h, 0);
  put_u64(h, payload.size());
  put_u64(h, z.size());
  put_u32(h, crc(payload, payload.size()));
  put_u32(h, crc(h, h.size()));
  return h + z;
}

// Expects decode to fail with an InputError whose message names the origin
// and contains `needle`.
void expect_input_error(const std::string& bytes, const std::string& needle) {
  try {
    decode_topology(bytes, "test.hmt");
    ADD_FAILURE() << "no error; expected one containing '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.code(), ExitCode::kInput);
    const std::string msg = e.what();
    EXPECT_NE(msg.find("test.hmt"), std::string::npos) << msg;
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
  }
}

// Expects decoding a run's map file (a session) to fail with an InputError
// containing `needle`.
void expect_session_error(const std::string& bytes, const std::string& needle) {
  try {
    decode_session(bytes, "x.bin");
    ADD_FAILURE() << "no error; expected one containing '" << needle << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------ tests

TEST(TopologyFile, RoundTripRestoresEverythingExactly) {
  TempDir dir;
  const Fixture f = sample_topology();
  const std::string path = dir.file("map.hmt");
  save_topology(path, f.map, f.hypotheses);
  const TopologySnapshot got = load_topology(path);
  expect_same(got, f);
  // The loaded map is a working map: arcs fuse, hypotheses give a PMF.
  EXPECT_NEAR(position_pmf(got.hypotheses).at(2), 1.0, 1e-12);
  EXPECT_EQ(got.map.area(0).map->logodds({0, 0}),
            f.map.area(0).map->logodds({0, 0}));
  // Saving what was loaded gives the same bytes.
  EXPECT_EQ(encode_topology(got.map, got.hypotheses), read_bytes(path));
  // No temporary left next to the file.
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir.file(""))) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1u);
}

TEST(TopologyFile, EmptyMapRoundTrips) {
  const std::string bytes = encode_topology(HmtMap(), {});
  const TopologySnapshot got = decode_topology(bytes, "empty");
  EXPECT_EQ(got.map.area_count(), 0u);
  EXPECT_TRUE(got.map.arcs().empty());
  EXPECT_TRUE(got.hypotheses.empty());
}

TEST(TopologyFile, ReadsVersion1WithoutKeyframeSteps) {
  auto one_keyframe = [](bool with_step) {
    std::string s = one_root_area(1);
    append_keyframe(s, with_step);
    s.push_back(0);  // no map
    put_u32(s, 0);   // no arcs
    put_u32(s, 0);   // no hypotheses
    return s;
  };
  const TopologySnapshot v1 = decode_topology(wrap(one_keyframe(false), kTopologyMagic, 1), "v1");
  const TopologySnapshot v2 = decode_topology(wrap(one_keyframe(true), kTopologyMagic, 2), "v2");
  for (const TopologySnapshot* t : {&v1, &v2}) {
    ASSERT_EQ(t->map.area(0).keyframes.size(), 1u);
    EXPECT_EQ(t->map.area(0).keyframes[0].pose.theta, 0.5);
    EXPECT_EQ(t->map.area(0).keyframes[0].scan.timestamp, 3.0);
  }
  EXPECT_EQ(v1.map.area(0).keyframes[0].step, kUnknownStep);
  EXPECT_EQ(v2.map.area(0).keyframes[0].step, 42u);
  // A version 1 payload labelled version 2 is refused: its bytes, shifted
  // by the step, give a beam count the data cannot hold.
  expect_input_error(wrap(one_keyframe(false), kTopologyMagic, 2),
                     "count of beams (1073741824) exceeds the remaining data");
}

TEST(TopologyFile, OnlyAllocatedTilesAreStoredAndDeflated) {
  // Two tiles 3000 tiles apart, plus a block of uniform free space: the
  // file holds the tiles, not their bounding box, and deflates the rest.
  HmtMap m;
  m.add_area(0);
  grid::OccupancyGrid g(0.05);
  g.mutable_logodds({-48000, 5}) = 40;
  g.mutable_logodds({48000, 5}) = 40;
  for (int y = 0; y < 320; ++y)
    for (int x = 0; x < 320; ++x) g.mutable_logodds({x, y + 992}) = -20;
  m.archive_map(0, g);
  const std::string bytes = encode_topology(m, {});
  EXPECT_EQ(g.tile_count(), 102u);
  EXPECT_LT(bytes.size(), 4000u);  // vs 102 * 4 KiB of cells
  const TopologySnapshot got = decode_topology(bytes, "sparse");
  EXPECT_EQ(got.map.area(0).map->tile_count(), 102u);
  EXPECT_EQ(got.map.area(0).map->logodds({48000, 5}), 40);
  EXPECT_EQ(got.map.area(0).map->logodds({319, 1311}), -20);
  EXPECT_FALSE(got.map.area(0).map->known({0, 5}));
}

TEST(TopologyFile, TruncatedFilesAreInputErrors) {
  const Fixture f = sample_topology();
  const std::string bytes = encode_topology(f.map, f.hypotheses);
  ASSERT_GT(bytes.size(), 1000u);
  expect_input_error("", "is empty");
  for (size_t n : {size_t{3}, size_t{8}, size_t{20}, size_t{39}})
    expect_input_error(bytes.substr(0, n), "truncated");
  for (size_t n : {size_t{40}, size_t{41}, bytes.size() / 2, bytes.size() - 1})
    expect_input_error(bytes.substr(0, n), "truncated");
  // And through the file API.
  TempDir dir;
  write_bytes(dir.file("cut.hmt"), bytes.substr(0, bytes.size() - 7));
  try {
    load_topology(dir.file("cut.hmt"));
    ADD_FAILURE() << "a truncated file loaded";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cut.hmt' is truncated"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_topology(dir.file("missing.hmt")), InputError);
}

TEST(TopologyFile, CorruptFilesAreInputErrors) {
  const Fixture f = sample_topology();
  const std::string good = encode_topology(f.map, f.hypotheses);
  std::string s = good;
  s[0] = 'X';
  expect_input_error(s, "bad magic");
  expect_input_error("PK\x03\x04 something else entirely, long enough",
                     "bad magic");
  s = good;
  s[8] = 3;  // version 3
  expect_input_error(s, "format version 3; this build reads version 1 to 2");
  s = good;
  s[20] ^= 0x10;  // the payload size
  expect_input_error(s, "header checksum");
  s = good;
  s[good.size() / 2] ^= 0x5a;  // inside the deflated data
  expect_input_error(s, "corrupt");
  expect_input_error(good + "x", "unexpected bytes");
  // Whatever byte is damaged, the answer is an InputError (never a crash,
  // a bad_alloc or a silently different map). A few bits of a deflate
  // stream do not change what it inflates to (e.g. the code lengths of
  // symbols a block never uses); such a file loads back the very same map,
  // which the checksum of the inflated payload guarantees and this checks.
  Random rng(1);
  int rejected = 0;
  for (int i = 0; i < 200; ++i) {
    s = good;
    const size_t at =
        static_cast<size_t>(rng.uniform(0, static_cast<double>(good.size())));
    s[at] =
        static_cast<char>(s[at] ^ (1 + static_cast<int>(rng.uniform(0, 255))));
    try {
      const TopologySnapshot got = decode_topology(s, "flip");
      EXPECT_GE(at, kTopologyHeaderSize) << "a damaged header was accepted";
      EXPECT_EQ(encode_topology(got.map, got.hypotheses), good) << "byte " << at;
    } catch (const InputError&) {
      ++rejected;
    }
  }
  EXPECT_GE(rejected, 190);
}

TEST(TopologyFile, InconsistentContentIsAnInputError) {
  // Checksum-valid files whose content breaks an invariant (as a file
  // written by other software could): built from the payload of a two-area
  // map, whose last 8 bytes are the arc and hypothesis counts (both 0).
  HmtMap m;
  m.add_area(0);
  m.add_area(1, {0, Pose2D(1, 0, 0), 10, 1.0});
  const std::string base = unwrap(encode_topology(m, {}));
  ASSERT_EQ(base.substr(base.size() - 8), std::string(8, '\0'));
  const std::string head = base.substr(0, base.size() - 8);
  EXPECT_NO_THROW(decode_topology(wrap(base), "ok"));

  auto arc = [&](uint32_t from, uint32_t to, double var) {
    std::string s = head;
    put_u32(s, 1);
    put_u32(s, from);
    put_u32(s, to);
    put_f64(s, 1.0);
    put_f64(s, 0.0);
    put_f64(s, 0.0);
    for (int i = 0; i < 9; ++i) put_f64(s, i % 4 == 0 ? var : 0.0);
    put_u32(s, 1);
    return s;
  };
  std::string s = arc(0, 1, 0.1);
  put_u32(s, 0);
  EXPECT_NO_THROW(decode_topology(wrap(s), "ok"));
  s = arc(0, 7, 0.1);
  put_u32(s, 0);
  expect_input_error(wrap(s), "does not exist");
  s = arc(0, 1, 0.0);
  put_u32(s, 0);
  expect_input_error(wrap(s), "positive definite");
  s = arc(1, 0, 0.1);
  put_u32(s, 0);
  expect_input_error(wrap(s), "ascending");

  // A hypothesis in an area the map does not have.
  s = head;
  put_u32(s, 0);  // no arcs
  put_u32(s, 1);
  put_f64(s, 0.0);
  put_u32(s, 2);
  put_u32(s, 0);
  put_u64(s, 0);
  put_u32(s, 9);
  put_u64(s, 5);
  expect_input_error(wrap(s), "hypothesis 0");
  // Extra bytes, and a payload that stops short.
  expect_input_error(wrap(base + "z"), "unexpected data");
  expect_input_error(wrap(base.substr(0, base.size() - 3)), "payload ends");
  // A count that cannot fit the data left.
  s = head;
  put_u32(s, 0xffffffffu);
  expect_input_error(wrap(s), "exceeds the remaining data");
}

TEST(TopologyFile, TilesFarApartAreRefusedBeforeTheirTableIsAllocated) {
  // A map's tile table is dense over its tiles' bounding box: two tiles
  // 3000 tiles apart in both directions, a few dozen bytes once deflated,
  // would claim 3001^2 table slots (144 MB). The box may be the tiles' own
  // square widened by a gap of 128 tiles (odometry jumps), or 4096 slots
  // per tile (OnlyAllocatedTilesAreStoredAndDeflated), no more.
  auto one_map = [](int32_t tx, int32_t ty) {
    std::string s = one_root_area(0);
    s.push_back(1);  // has a map
    put_f64(s, 0.05);
    put_u32(s, 2);
    for (const auto& [x, y] : {std::pair<int32_t, int32_t>{0, 0}, {tx, ty}}) {
      put_u32(s, static_cast<uint32_t>(x));
      put_u32(s, static_cast<uint32_t>(y));
      s.append(4 * 1024, '\0');
    }
    put_u32(s, 0);  // no arcs
    put_u32(s, 0);  // no hypotheses
    return s;
  };
  EXPECT_NO_THROW(decode_topology(wrap(one_map(100, 0)), "near"));
  // 2 tiles: a box of up to max(130 x 130, 2 x 4096) tiles.
  EXPECT_NO_THROW(decode_topology(wrap(one_map(129, -129)), "at the bound"));
  expect_input_error(wrap(one_map(130, 129)), "implausibly large area");
  expect_input_error(wrap(one_map(3000, -3000)), "implausibly large area");
}

TEST(TopologyFile, FailedSavesLeaveTheEarlierFileIntact) {
  TempDir dir;
  const Fixture f = sample_topology();
  const std::string path = dir.file("map.hmt");
  save_topology(path, f.map, f.hypotheses);
  const std::string before = read_bytes(path);
  // A hypothesis naming an area the map lacks is refused before writing.
  std::vector<TopologicalHypothesis> bad = f.hypotheses;
  enter_area(bad[0], 42, 1000);
  EXPECT_THROW(save_topology(path, f.map, bad), std::invalid_argument);
  EXPECT_EQ(read_bytes(path), before);
  // An unwritable destination is an OutputError.
  try {
    save_topology(dir.file("no/such/dir/map.hmt"), f.map, f.hypotheses);
    ADD_FAILURE() << "saved into a missing directory";
  } catch (const OutputError& e) {
    EXPECT_EQ(e.code(), ExitCode::kOutput);
  }
  EXPECT_EQ(read_bytes(path), before);
}

}  // namespace
}  // namespace hmt::topology

namespace hmt::topology {
namespace {

// Two hypotheses of one run, as hmt_map.bin holds them: each its own map
// (its current area archived) and path.
Session sample_session() {
  const Fixture f = sample_topology();
  Session s;
  s.steps = 300;
  s.time = 1.6e9 + 12.5;
  SessionHypothesis a;
  a.id = 3;
  a.map = f.map;
  a.map.archive_map(2, grid::OccupancyGrid(0.05));
  a.topo = f.hypotheses[0];
  a.robot = Pose2D(1.25, -0.5, 0.3);
  a.aam_from_area = Pose2D(10.0, 2.0, -1.0);
  SessionHypothesis b = a;
  b.id = 8;
  b.topo = f.hypotheses[1];
  b.topo.log_weight = -3.0;
  b.robot = Pose2D(-2.0, 0.5, 3.0);
  // Closures TSBI made and TLCA has not accepted: one between areas an arc
  // already joined, one between areas that were not adjacent.
  ClosureRecord c1;
  c1.from = 2;
  c1.to = 0;
  c1.step = 280;
  c1.measurement = PoseGaussian(Pose2D(-1.5, 2.25, 0.4), correlated(5));
  ClosureRecord c2 = c1;
  c2.from = 1;
  c2.to = 0;
  c2.step = 290;
  c2.arc_before = *f.map.find_arc(0, 1);
  b.pending_closures = {c1, c2};
  s.hypotheses = {a, b};
  // The area abstraction's graph.
  Random rng(7);
  s.area_graph = {random_keyframe(rng, 181), random_keyframe(rng, 361)};
  return s;
}

TEST(SessionFile, RoundTripRestoresEveryHypothesisExactly) {
  TempDir dir;
  const Session s = sample_session();
  const std::string path = dir.file("hmt_map.bin");
  save_session(path, s);
  const Session got = load_session(path);
  EXPECT_EQ(got.steps, s.steps);
  EXPECT_EQ(bits(got.time), bits(s.time));
  ASSERT_EQ(got.hypotheses.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE("hypothesis " + std::to_string(i));
    const SessionHypothesis& g = got.hypotheses[i];
    const SessionHypothesis& w = s.hypotheses[i];
    EXPECT_EQ(g.id, w.id);
    expect_same_pose(g.robot, w.robot);
    expect_same_pose(g.aam_from_area, w.aam_from_area);
    EXPECT_EQ(g.topo.path, w.topo.path);
    EXPECT_EQ(bits(g.topo.log_weight), bits(w.topo.log_weight));
    EXPECT_EQ(g.map.area_ids(), w.map.area_ids());
    EXPECT_EQ(g.map.arcs().size(), w.map.arcs().size());
    EXPECT_EQ(g.map.area(0).map->logodds({0, 0}), w.map.area(0).map->logodds({0, 0}));
    ASSERT_EQ(g.pending_closures.size(), w.pending_closures.size());
    for (size_t k = 0; k < w.pending_closures.size(); ++k) {
      const ClosureRecord &gc = g.pending_closures[k], &wc = w.pending_closures[k];
      EXPECT_EQ(gc.from, wc.from);
      EXPECT_EQ(gc.to, wc.to);
      EXPECT_EQ(gc.step, wc.step);
      expect_same_pose(gc.measurement.mean, wc.measurement.mean);
      EXPECT_EQ(gc.measurement.cov, wc.measurement.cov);
      ASSERT_EQ(gc.arc_before.has_value(), wc.arc_before.has_value());
      if (wc.arc_before) {
        EXPECT_EQ(gc.arc_before->from, wc.arc_before->from);
        EXPECT_EQ(gc.arc_before->to, wc.arc_before->to);
        expect_same_pose(gc.arc_before->pose.mean, wc.arc_before->pose.mean);
        EXPECT_EQ(gc.arc_before->pose.cov, wc.arc_before->pose.cov);
        EXPECT_EQ(gc.arc_before->measurements, wc.arc_before->measurements);
      }
    }
  }
  EXPECT_EQ(got.hypotheses[1].pending_closures.size(), 2u);
  expect_same_keyframes(got.area_graph, s.area_graph);
  EXPECT_EQ(encode_session(got), read_bytes(path));
}

TEST(SessionFile, MapsHypothesesShareAreStoredAndLoadedOnce) {
  Session s = sample_session();
  grid::OccupancyGrid big(0.05);
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x) big.mutable_logodds({x, y}) = (x * 7 + y * 3) % 50;
  s.hypotheses[0].map.archive_map(0, big);
  s.hypotheses[1].map = s.hypotheses[0].map;  // shares area 0's map
  Session one = s;
  one.hypotheses.resize(1);
  const std::string both = encode_session(s), single = encode_session(one);
  // The second hypothesis adds its paths and arcs, not a second copy of the
  // 40 000-cell map.
  EXPECT_LT(both.size(), single.size() + 1000);
  const Session got = decode_session(both, "shared.bin");
  ASSERT_EQ(got.hypotheses.size(), 2u);
  EXPECT_EQ(got.hypotheses[0].map.area(0).map, got.hypotheses[1].map.area(0).map);
  EXPECT_EQ(got.hypotheses[1].map.area(0).map->logodds({10, 20}), (10 * 7 + 20 * 3) % 50);
  // A map of its own stays its own.
  Session apart = s;
  apart.hypotheses[1].map.archive_map(0, big);
  EXPECT_GT(encode_session(apart).size(), single.size() + 1000);
}

// A session payload written from the documented layout, up to and
// including the one hypothesis's path (version 3 adds its closures after
// it): `maps` empty grids stored, areas 0 and 1 both naming map
// `map_index`, the hypothesis in area 0. With one map and index 0 it is the
// smallest valid file.
std::string session_payload(uint32_t maps, uint32_t map_index) {
  std::string p;
  put_u64(p, 1);    // steps
  put_f64(p, 2.0);  // time
  put_u32(p, maps);  // maps stored
  for (uint32_t m = 0; m < maps; ++m) {
    put_f64(p, 0.05);  // resolution
    put_u32(p, 0);     // tiles
  }
  put_u32(p, 1);    // hypotheses
  put_u32(p, 0);    // its id
  for (int i = 0; i < 6; ++i) put_f64(p, 0.0);  // robot, area abstraction frame
  put_u32(p, 2);                                // areas 0 and 1
  for (uint32_t id : {0u, 1u}) {
    put_u32(p, id);
    put_u32(p, id == 0 ? 0xffffffffu : 0u);       // parent
    for (int i = 0; i < 3; ++i) put_f64(p, 0.0);  // origin
    put_u64(p, 0);                                // created step
    put_f64(p, 0.0);                              // created time
    put_u32(p, 0);                                // keyframes
    put_u32(p, map_index);                        // map index
  }
  put_u32(p, 0);  // arcs
  put_u32(p, 1);  // paths
  put_f64(p, 0.0);
  put_u32(p, 1);
  put_u32(p, 0);
  put_u64(p, 0);
  return p;
}
std::string minimal_session_payload() { return session_payload(1, 0); }

TEST(SessionFile, BadFilesAreInputErrorsNamingTheProblem) {
  const Session s = sample_session();
  const std::string bytes = encode_session(s);
  expect_session_error(bytes.substr(0, bytes.size() - 7), "truncated");
  expect_session_error(bytes.substr(0, 20), "truncated");
  expect_session_error("", "empty");
  // A topology file is not a map file of a run.
  const Fixture f = sample_topology();
  expect_session_error(encode_topology(f.map, f.hypotheses), "not an HMT map file");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  expect_session_error(flipped, "corrupt");
  // An area naming a map the file does not store (checksums valid).
  expect_session_error(wrap(session_payload(0, 5), kSessionMagic, kSessionFormatVersion),
                       "map index 5 beyond the 0 maps stored");
  // A hypothesis whose current area has no map cannot be continued.
  Session no_map = s;
  no_map.hypotheses[0].map = f.map;  // area 2 (current) not archived
  expect_session_error(encode_session(no_map), "current area has no map");
}

TEST(SessionFile, ReadsEarlierVersionsWithoutClosuresOrGraph) {
  const std::string p = minimal_session_payload();
  const Session v2 = decode_session(wrap(p, kSessionMagic, 2), "v2.bin");
  ASSERT_EQ(v2.hypotheses.size(), 1u);
  EXPECT_TRUE(v2.hypotheses[0].pending_closures.empty());
  EXPECT_TRUE(v2.area_graph.empty());
  // The same payload is short of its closure count in version 3...
  expect_session_error(wrap(p, kSessionMagic, 3), "payload ends inside pending closures");
  // ... which, given (no closures), makes a version 3 file without a graph;
  std::string p3 = p;
  put_u32(p3, 0);
  const Session v3 = decode_session(wrap(p3, kSessionMagic, 3), "v3.bin");
  EXPECT_TRUE(v3.area_graph.empty());
  // version 4 needs the graph's count too...
  expect_session_error(wrap(p3, kSessionMagic, 4), "payload ends inside area graph keyframes");
  // ... and a version this build does not know is refused, naming both.
  expect_session_error(wrap(p3 + std::string(4, '\0'), kSessionMagic, 6),
                       "format version 6; this build reads version 2 to 5");
  // Keyframes carry their steps from version 5 on; a version 4 file's are
  // not known.
  std::string p4 = p3;
  put_u32(p4, 1);  // one area graph keyframe
  std::string p5 = p4;
  append_keyframe(p4, false);
  append_keyframe(p5, true);
  const Session v4 = decode_session(wrap(p4, kSessionMagic, 4), "v4.bin");
  ASSERT_EQ(v4.area_graph.size(), 1u);
  EXPECT_EQ(v4.area_graph[0].step, kUnknownStep);
  EXPECT_EQ(v4.area_graph[0].pose.y, 2.0);
  const Session v5 = decode_session(wrap(p5, kSessionMagic, 5), "v5.bin");
  ASSERT_EQ(v5.area_graph.size(), 1u);
  EXPECT_EQ(v5.area_graph[0].step, 42u);
  EXPECT_EQ(v5.area_graph[0].scan.ranges, (std::vector<float>{1.0f, 2.0f}));
}

TEST(SessionFile, BadAreaGraphIsAnInputError) {
  Session s = sample_session();
  s.area_graph[1].pose.y = std::nan("");
  expect_session_error(encode_session(s), "area graph: non-finite keyframe pose");
}

TEST(SessionFile, BadPendingClosuresAreInputErrorsNamingThem) {
  auto with_closure = [](uint32_t from, uint32_t to, double cov_diag, uint8_t has_arc,
                         uint32_t arc_from, uint32_t arc_to) {
    std::string p = minimal_session_payload();
    put_u32(p, 1);  // one closure
    put_u32(p, from);
    put_u32(p, to);
    put_u64(p, 1);
    for (int i = 0; i < 3; ++i) put_f64(p, 0.0);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) put_f64(p, r == c ? cov_diag : 0.0);
    p.push_back(static_cast<char>(has_arc));
    if (has_arc == 1) {
      put_u32(p, arc_from);
      put_u32(p, arc_to);
      for (int i = 0; i < 3; ++i) put_f64(p, 0.0);
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) put_f64(p, r == c ? 0.01 : 0.0);
      put_u32(p, 1);
    }
    put_u32(p, 0);  // no area graph keyframes
    return wrap(p, kSessionMagic, kSessionFormatVersion);
  };
  const Session ok = decode_session(with_closure(1, 0, 0.01, 1, 0, 1), "ok.bin");
  ASSERT_EQ(ok.hypotheses[0].pending_closures.size(), 1u);
  EXPECT_TRUE(ok.hypotheses[0].pending_closures[0].arc_before.has_value());
  expect_session_error(with_closure(1, 9, 0.01, 0, 0, 0),
                       "hypothesis 0, closure 0: 1-9 are not two areas of its map");
  expect_session_error(with_closure(1, 1, 0.01, 0, 0, 0), "1-1 are not two areas of its map");
  expect_session_error(with_closure(1, 0, -1.0, 0, 0, 0), "measurement covariance is not");
  expect_session_error(with_closure(1, 0, 0.01, 2, 0, 0), "bad arc flag");
  expect_session_error(with_closure(1, 0, 0.01, 1, 1, 0),
                       "closure 0: arc 1-0: areas not in ascending order");
  expect_session_error(with_closure(1, 0, 0.01, 1, 0, 7), "its arc before joins other areas");
}

}  // namespace
}  // namespace hmt::topology
