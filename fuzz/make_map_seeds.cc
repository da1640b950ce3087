// Writes the seed corpora of fuzz_topology and fuzz_session: small topology
// and HMT map files made by the library's own encoder, each both as a whole
// file (first byte 0) and as its inflated payload (first byte 1, which the
// targets wrap in a valid container). Run once when the formats change:
//   build-fuzz/fuzz/make_map_seeds fuzz/corpus
#include <zlib.h>

#include <cmath>
#include <fstream>
#include <string>

#include "fuzz_support.h"
#include "hmt/topology/topology_file.h"

namespace hmt::topology {
namespace {

Keyframe keyframe(double x, int beams) {
  Keyframe k;
  k.pose = Pose2D(x, 0.5, 0.25);
  k.scan.timestamp = 100.0 + x;
  k.scan.angle_min = static_cast<float>(-M_PI / 2);
  k.scan.angle_increment = static_cast<float>(M_PI / (beams - 1));
  k.scan.max_range = 30.0f;
  k.scan.sensor_pose = Pose2D(0.2, 0.0, 0.0);
  for (int i = 0; i < beams; ++i) {
    k.scan.ranges.push_back(1.0f + 0.5f * static_cast<float>(i));
    k.scan.valid.push_back(i % 3 != 0);
  }
  return k;
}

// One tile's worth of cells, some with hit statistics.
grid::OccupancyGrid small_grid() {
  grid::OccupancyGrid g(0.05);
  for (int i = 0; i < 20; ++i) {
    grid::Cell c;
    c.logodds = static_cast<int8_t>(i * 6 - 60);
    c.hits = static_cast<uint8_t>(i % 4);
    c.hx = static_cast<int8_t>(i);
    c.hy = static_cast<int8_t>(-i);
    g.set_cell({i, i / 2}, c);
  }
  return g;
}

Eigen::Matrix3d cov(double s) {
  Eigen::Matrix3d c;
  c << 0.04, 0.01, 0.002, 0.01, 0.09, -0.003, 0.002, -0.003, 0.0025;
  return s * c;
}

HmtMap two_areas() {
  HmtMap m;
  m.add_area(0, {kNoArea, Pose2D(), 0, 100.0});
  m.add_area(1, {0, Pose2D(4.5, -0.5, 0.7), 40, 114.0});
  m.add_keyframe(0, keyframe(0.0, 5));
  m.add_keyframe(1, keyframe(1.0, 3));
  m.archive_map(0, small_grid());
  m.archive_map(1, grid::OccupancyGrid(0.1));
  m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(4.5, -0.5, 0.7), cov(1)));
  return m;
}

TopologicalHypothesis path(std::initializer_list<AreaId> areas) {
  TopologicalHypothesis h;
  uint64_t step = 0;
  for (AreaId a : areas) enter_area(h, a, step += 20);
  h.log_weight = -0.5;
  return h;
}

std::string inflate_payload(const std::string& file) {
  uint64_t size = 0;
  for (int i = 0; i < 8; ++i) size |= uint64_t(uint8_t(file[16 + i])) << (8 * i);
  std::string out(size, '\0');
  uLongf got = size;
  fuzz::check(uncompress(reinterpret_cast<Bytef*>(out.data()), &got,
                         reinterpret_cast<const Bytef*>(file.data() + kTopologyHeaderSize),
                         file.size() - kTopologyHeaderSize) == Z_OK,
              "cannot inflate a seed");
  return out;
}

void write_seed(const std::string& path, char mode, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.put(mode);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  fuzz::check(out.good(), "cannot write " + path);
}

void write_both(const std::string& dir, const std::string& name, const std::string& file) {
  write_seed(dir + "/" + name + ".file", 0, file);
  write_seed(dir + "/" + name + ".payload", 1, inflate_payload(file));
}

}  // namespace
}  // namespace hmt::topology

int main(int argc, char** argv) {
  using namespace hmt::topology;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR\n", argv[0]);
    return 2;
  }
  const std::string topo = std::string(argv[1]) + "/fuzz_topology";
  const std::string sess = std::string(argv[1]) + "/fuzz_session";

  write_both(topo, "empty", encode_topology(HmtMap(), {}));
  const HmtMap m = two_areas();
  write_both(topo, "two-areas", encode_topology(m, {path({0, 1}), path({0, 1, 0})}));
  HmtMap three = m;
  three.add_area(5, {1, hmt::Pose2D(-1, 2, -3.0), 60, 120.0});
  three.add_arc_measurement(5, 1, PoseGaussian(hmt::Pose2D(1, -2, 3.0), cov(2)));
  write_both(topo, "three-areas", encode_topology(three, {path({0, 1, 5})}));

  Session s;
  s.steps = 60;
  s.time = 120.0;
  SessionHypothesis a;
  a.id = 1;
  a.map = m;
  a.topo = path({0, 1, 0});
  a.robot = hmt::Pose2D(0.5, 0.25, 0.1);
  a.aam_from_area = hmt::Pose2D(2.0, 1.0, -0.5);
  s.hypotheses = {a};
  write_both(sess, "one-hypothesis", encode_session(s));
  SessionHypothesis b = a;
  b.id = 4;
  b.topo = path({0, 1});
  b.map.archive_map(1, small_grid());
  ClosureRecord c;
  c.from = 1;
  c.to = 0;
  c.step = 55;
  c.measurement = PoseGaussian(hmt::Pose2D(-1.5, 2.25, 0.4), cov(5));
  c.arc_before = *b.map.find_arc(0, 1);
  b.pending_closures = {c};
  s.hypotheses = {a, b};
  write_both(sess, "two-hypotheses-closure", encode_session(s));
  return 0;
}
