#include "hmt/checkpoint/checkpoint.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>

#include "../../hybrid/tests/ring_world.h"
#include "hmt/common/error.h"
#include "hmt/topology/topology_file.h"
#include "hmt_test/scratch.h"

namespace hmt::checkpoint {
namespace {

namespace fs = std::filesystem;

framework::FrameworkOptions deterministic() {
  framework::FrameworkOptions o;
  o.mode = framework::Mode::kDeterministic;
  o.inbox_capacity = 8;
  return o;
}

// A file removed if the test passes.
std::string temp_path(const std::string& name) {
  return scratch::track(fs::temp_directory_path() /
                        ("hmt_checkpoint_" + name + "_" + std::to_string(::getpid()) + ".bin"))
      .string();
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << bytes;
}

// What the outputs are written from, as bytes: every hypothesis (maps, paths,
// robot poses, pending closures), the best path, the transitions, the
// acceptances and the traces.
std::string fingerprint(const framework::HmtSystem& s) {
  std::ostringstream os;
  os.precision(17);
  const hybrid::HybridFilter& f = s.filter();
  os << "session " << std::hash<std::string>()(topology::encode_session(f.session())) << '\n';
  for (const auto& seg : f.final_trajectory()) {
    os << "seg " << seg.area << ' ' << seg.first_step;
    for (const Pose2D& p : seg.poses) os << ' ' << p.x << ' ' << p.y << ' ' << p.theta;
    os << '\n';
  }
  for (const auto& t : f.transitions()) {
    os << "event " << t.step << ' ' << t.hypothesis << ' ' << t.from_area;
    for (const auto& o : t.outcomes) os << ' ' << o.area << ' ' << o.log_f << ' ' << o.probability;
    os << '\n';
  }
  for (const auto& a : f.acceptances()) os << "accept " << a.step << ' ' << a.closures.size() << '\n';
  for (const auto& t : s.traces()) {
    os << "trace " << t.step << ' ' << t.areas;
    for (const auto& [area, p] : t.pmf) os << ' ' << area << ':' << p;
    for (const auto& h : t.hypotheses) os << ' ' << h.id << '/' << h.ess;
    os << '\n';
  }
  const auto& st = f.stats();
  os << st.steps << ' ' << st.keyframes << ' ' << st.new_area_events << ' '
     << st.loop_closures_accepted << '\n';
  return os.str();
}

// A run of the ring world stopped after `cut` steps: its checkpoint is
// written to `path`, the system is then dropped unfinished (as a killed
// process would be).
void run_and_save(const Log& log, size_t cut, const std::string& path, size_t* memory = nullptr) {
  framework::HmtSystem s(testing_ring::ring_options(), deterministic());
  s.start();
  uint32_t crc = 0;
  for (size_t i = 0; i < cut; ++i) {
    s.feed(log.steps[i]);
    crc = log_fingerprint(crc, log.steps[i]);
  }
  RunIdentity id;
  id.config = "[metric_slam]\nparticles = 30\n";
  id.input = "ring world";
  id.steps = cut;
  id.log_crc = crc;
  s.run_between_steps([&] {
    save(path, id, s);
    if (memory) *memory = s.filter().map_memory_bytes();
  });
}

TEST(Checkpoint, AResumedRunEndsExactlyAsTheUninterruptedOne) {
  const auto run = testing_ring::ring_run(7);
  const Log& log = run.log;
  framework::HmtSystem whole(testing_ring::ring_options(), deterministic());
  whole.start();
  for (const LogStep& st : log.steps) whole.feed(st);
  whole.finish();
  const std::string expected = fingerprint(whole);
  ASSERT_GT(whole.filter().stats().new_area_events, 2u);
  ASSERT_GT(whole.filter().stats().loop_closures_accepted, 0u);

  const std::string path = temp_path("resume");
  // Cuts early (one area), in the middle, and late (after the loop closed):
  // every part of the state must carry over.
  for (const size_t cut : {size_t{3}, log.steps.size() / 3, log.steps.size() / 2,
                           log.steps.size() * 4 / 5, log.steps.size() - 1}) {
    SCOPED_TRACE("cut after " + std::to_string(cut) + " steps");
    size_t memory_saved = 0;
    run_and_save(log, cut, path, &memory_saved);
    const RunIdentity id = read_identity(path);
    EXPECT_EQ(id.steps, cut);
    EXPECT_EQ(id.input, "ring world");
    EXPECT_EQ(id.config, "[metric_slam]\nparticles = 30\n");

    framework::HmtSystem resumed(testing_ring::ring_options(), deterministic());
    EXPECT_EQ(load(path, resumed).steps, cut);
    // Tiles and maps shared copy-on-write are shared again, not copied.
    EXPECT_EQ(resumed.filter().map_memory_bytes(), memory_saved);
    EXPECT_EQ(resumed.steps_fed(), cut);
    resumed.start();
    for (size_t i = cut; i < log.steps.size(); ++i) resumed.feed(log.steps[i]);
    resumed.finish();
    EXPECT_EQ(fingerprint(resumed), expected);
  }
}

// Loading then saving gives the file back byte for byte: every member read
// is a member written, in the same order (the timings included).
TEST(Checkpoint, ALoadedStateSavesToTheSameBytes) {
  const auto run = testing_ring::ring_run(3);
  const std::string a = temp_path("bytes_a"), b = temp_path("bytes_b");
  run_and_save(run.log, run.log.steps.size() / 2, a);
  const RunIdentity id = read_identity(a);
  framework::HmtSystem s(testing_ring::ring_options(), deterministic());
  load(a, s);
  s.start();
  s.run_between_steps([&] { save(b, id, s); });
  s.finish();
  const std::string bytes_a = slurp(a), bytes_b = slurp(b);
  EXPECT_EQ(bytes_a.size(), bytes_b.size());
  EXPECT_TRUE(bytes_a == bytes_b);
}

// Every damaged file is refused with an InputError that names the file and
// the problem, before any state is touched.
TEST(Checkpoint, DamagedFilesAreRefusedByName) {
  const auto run = testing_ring::ring_run(3);
  const std::string good = temp_path("good"), bad = temp_path("bad");
  run_and_save(run.log, 40, good);
  const std::string bytes = slurp(good);
  ASSERT_GT(bytes.size(), kCheckpointHeaderSize + 100);

  const auto expect_refused = [&](const std::string& content, const std::string& why) {
    spit(bad, content);
    try {
      read_identity(bad);
      ADD_FAILURE() << "accepted: " << why;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
    framework::HmtSystem s(testing_ring::ring_options(), deterministic());
    EXPECT_THROW(load(bad, s), InputError) << why;
  };
  expect_refused(bytes.substr(0, 20), "shorter than its header");
  expect_refused(bytes.substr(0, bytes.size() / 2), "truncated");
  expect_refused(bytes + "x", "trailing bytes");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  expect_refused(flipped, "corrupt payload");
  std::string header = bytes;
  header[17] ^= 0x01;  // the payload size, under the header's checksum
  expect_refused(header, "corrupt header");
  std::string magic = bytes;
  magic[0] = 'X';
  expect_refused(magic, "not an hmt-slam checkpoint");
  expect_refused("", "shorter than its header");
  // Another format version (an older build's checkpoint), its header
  // otherwise intact: refused by name, not misread.
  std::string older = bytes;
  const uint32_t version = kCheckpointFormatVersion - 1;
  for (int i = 0; i < 4; ++i) older[8 + i] = static_cast<char>((version >> (8 * i)) & 0xff);
  const auto crc = static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(older.data()), 28));
  for (int i = 0; i < 4; ++i) older[28 + i] = static_cast<char>((crc >> (8 * i)) & 0xff);
  expect_refused(older, "format version " + std::to_string(version) + ", this hmt-slam reads version " +
                            std::to_string(kCheckpointFormatVersion));

  try {
    read_identity(bad + ".missing");
    ADD_FAILURE() << "a missing file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
}

// A checkpoint replaces the previous one atomically: a write that fails
// leaves the earlier file as it was.
TEST(Checkpoint, AFailedWriteLeavesTheEarlierCheckpoint) {
  const auto run = testing_ring::ring_run(3);
  const std::string path = temp_path("atomic");
  run_and_save(run.log, 30, path);
  const std::string before = slurp(path);
  // A folder in the temporary file's place makes the next write fail.
  const std::string blocker = path + ".tmp." + std::to_string(::getpid());
  fs::create_directories(scratch::track(blocker));
  EXPECT_THROW(run_and_save(run.log, 60, path), OutputError);
  EXPECT_EQ(slurp(path), before);
}

TEST(Checkpoint, TheLogFingerprintSeesEveryPart) {
  LogStep a;
  a.timestamp = 1.0;
  a.odometry_increment = {0.1, 0.0, 0.01};
  a.scan.ranges = {1.0f, 2.0f, 3.0f};
  const uint32_t base = log_fingerprint(0, a);
  LogStep b = a;
  b.timestamp = 1.5;
  EXPECT_NE(log_fingerprint(0, b), base);
  b = a;
  b.odometry_increment.theta = 0.02;
  EXPECT_NE(log_fingerprint(0, b), base);
  b = a;
  b.scan.ranges[2] = 3.5f;
  EXPECT_NE(log_fingerprint(0, b), base);
  EXPECT_NE(log_fingerprint(base, a), base);  // chained: order and count matter
}

}  // namespace
}  // namespace hmt::checkpoint
