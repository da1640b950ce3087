#include "hmt/topology/topology_file.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "hmt/common/error.h"
#include "hmt/common/files.h"
#include "hmt/common/int_div.h"

namespace hmt::topology {
namespace {

constexpr int kCellsPerTile = grid::kTileSize * grid::kTileSize;
// Deflate never expands data by more than this factor when inflating
// (its maximum compression ratio is about 1032:1).
constexpr uint64_t kMaxInflateRatio = 1040;
// A map's tile table is dense over the bounding box of its tiles (16 bytes
// a tile, allocated or not); refuse boxes larger than this many tiles (at
// 5 cm cells, 6.5 km a side) ...
constexpr int64_t kMaxTileBoxArea = int64_t{1} << 24;
// ... and than what the stored tiles can account for: a square of side
// (n + kMaxTileGap) for n tiles (a map's tiles are joined by the rays that
// made them, so its box is at most n x n, plus gaps where the odometry
// jumped: [input] max_step_motion, 10 m, is 7 tiles at 5 cm cells), or
// kMaxSlotsPerTile table slots per stored tile (64 KB of table per 4 KB
// tile: sparse maps stay loadable, and memory stays bounded by the data).
// Without this, two tiles far apart -- a few dozen bytes of deflated file
// -- would claim 256 MB each.
constexpr int64_t kMaxTileGap = 128;
constexpr int64_t kMaxSlotsPerTile = 4096;
// Tile coordinates whose cell indices fit comfortably in an int.
constexpr int32_t kMaxTileCoord = 1 << 25;

uint32_t crc_of(const char* data, size_t size) {
  return static_cast<uint32_t>(crc32_z(
      crc32_z(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(data), size));
}

// ---------------------------------------------------------------- writing

// Deflates a payload as it is written, so a large one (a session with many
// areas) never sits in memory whole, and keeps its inflated size and CRC for
// the header. Level 1: the tile planes are long runs that the fastest level
// already compresses well; higher levels cost seconds on a large run's map
// for a few percent of file size.
class Deflater {
 public:
  explicit Deflater(const char* who) : who_(who) {
    if (deflateInit(&zs_, Z_BEST_SPEED) != Z_OK)
      throw std::runtime_error(std::string(who_) + ": zlib initialisation failed");
  }
  ~Deflater() { deflateEnd(&zs_); }
  Deflater(const Deflater&) = delete;
  Deflater& operator=(const Deflater&) = delete;

  void feed(const char* data, size_t n) {
    crc_ = static_cast<uint32_t>(crc32_z(crc_, reinterpret_cast<const Bytef*>(data), n));
    size_ += n;
    run(data, n, Z_NO_FLUSH);
  }
  // The whole deflated stream; the Deflater is spent.
  std::string finish() {
    run(nullptr, 0, Z_FINISH);
    out_.resize(used_);
    return std::move(out_);
  }
  uint64_t size() const { return size_; }
  uint32_t crc() const { return crc_; }

 private:
  void run(const char* data, size_t n, int flush) {
    zs_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
    zs_.avail_in = static_cast<uInt>(n);  // callers feed chunks well under 4 GB
    for (;;) {
      if (used_ == out_.size()) out_.resize(std::max<size_t>(2 * out_.size(), 1 << 16));
      zs_.next_out = reinterpret_cast<Bytef*>(&out_[used_]);
      zs_.avail_out = static_cast<uInt>(out_.size() - used_);
      const int rc = deflate(&zs_, flush);
      used_ = out_.size() - zs_.avail_out;
      if (rc == Z_STREAM_END) return;
      if (rc != Z_OK && rc != Z_BUF_ERROR)
        throw std::runtime_error(std::string(who_) + ": zlib compression failed (" +
                                 std::to_string(rc) + ")");
      if (flush == Z_NO_FLUSH && zs_.avail_in == 0 && zs_.avail_out > 0) return;
    }
  }

  const char* who_;
  z_stream zs_{};
  std::string out_;
  size_t used_ = 0;
  uint64_t size_ = 0;
  uint32_t crc_ = static_cast<uint32_t>(crc32_z(0L, Z_NULL, 0));
};

class Writer {
 public:
  // Hands the bytes written so far to `d` whenever they pass kSpillBytes
  // (spill()) and at flush(); without a Deflater, bytes() keeps everything.
  explicit Writer(Deflater* d = nullptr) : sink_(d) {}
  void spill() {
    if (sink_ && out_.size() >= kSpillBytes) flush();
  }
  void flush() {
    if (!sink_ || out_.empty()) return;
    sink_->feed(out_.data(), out_.size());
    out_.clear();
  }
  void u8(uint8_t v) { out_.push_back(static_cast<char>(v)); }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i)
      out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i)
      out_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  void i32(int32_t v) { u32(static_cast<uint32_t>(v)); }
  void f32(float v) {
    uint32_t b;
    std::memcpy(&b, &v, sizeof b);
    u32(b);
  }
  void f64(double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    u64(b);
  }
  void pose(const Pose2D& p) {
    f64(p.x);
    f64(p.y);
    f64(p.theta);
  }
  void count(size_t n, const char* what) {
    if (n > 0xffffffffu)
      throw std::invalid_argument(std::string("encode_topology: too many ") +
                                  what);
    u32(static_cast<uint32_t>(n));
  }
  std::string& bytes() { return out_; }

 private:
  static constexpr size_t kSpillBytes = size_t{1} << 20;
  Deflater* sink_;
  std::string out_;
};

void write_grid(Writer& w, const grid::OccupancyGrid& g) {
  w.f64(g.resolution());
  grid::CellIndex lo, hi;
  std::vector<std::pair<int, int>> tiles;  // (tx, ty), ascending ty then tx
  if (g.bounds(&lo, &hi)) {
    const int tx0 = floor_div(lo.x, grid::kTileSize),
              ty0 = floor_div(lo.y, grid::kTileSize);
    const int tx1 = floor_div(hi.x, grid::kTileSize),
              ty1 = floor_div(hi.y, grid::kTileSize);
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx)
        if (g.tile(tx, ty)) tiles.emplace_back(tx, ty);
  }
  w.count(tiles.size(), "tiles");
  std::string plane(kCellsPerTile, '\0');
  for (const auto& [tx, ty] : tiles) {
    w.i32(tx);
    w.i32(ty);
    // The cells in the tile's storage order (index_in_tile).
    const grid::Tile& t = *g.tile(tx, ty);
    for (int field = 0; field < 4; ++field) {
      for (int i = 0; i < kCellsPerTile; ++i) {
        const grid::Cell c = t.cell(i);
        const uint8_t b = field == 0   ? static_cast<uint8_t>(c.logodds)
                          : field == 1 ? c.hits
                          : field == 2 ? static_cast<uint8_t>(c.hx)
                                       : static_cast<uint8_t>(c.hy);
        plane[static_cast<size_t>(i)] = static_cast<char>(b);
      }
      w.bytes() += plane;
    }
    w.spill();
  }
}

void write_scan(Writer& w, const LaserScan& s) {
  w.f64(s.timestamp);
  w.f32(s.angle_min);
  w.f32(s.angle_increment);
  w.f32(s.max_range);
  w.pose(s.sensor_pose);
  w.count(s.ranges.size(), "beams");
  for (float r : s.ranges) w.f32(r);
  for (uint8_t v : s.valid) w.u8(v);
}

// A keyframe list (an area's, the area abstraction's graph): u32 count
// (`list` names it in errors), then each keyframe's pose and scan.
void write_keyframes(Writer& w, const std::vector<Keyframe>& keyframes, const char* list,
                     const char* caller) {
  w.count(keyframes.size(), list);
  for (const Keyframe& k : keyframes) {
    if (k.scan.valid.size() != k.scan.ranges.size())
      throw std::invalid_argument(std::string(caller) +
                                  ": a keyframe's scan has different numbers of "
                                  "ranges and validity flags");
    w.pose(k.pose);
    w.u64(k.step);
    write_scan(w, k.scan);
  }
}

// Grids written once in a table (a session's hypotheses share most area
// maps): the index of each, in the order written.
using GridTable = std::map<const grid::OccupancyGrid*, uint32_t>;
constexpr uint32_t kNoGrid = 0xffffffffu;

// The topology payload of the layout in topology_file.h. With `grids`, each
// area's map is written as its u32 index in the table (kNoGrid: none)
// instead of the has_map byte and the grid.
void write_gaussian(Writer& w, const PoseGaussian& g) {
  w.pose(g.mean);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) w.f64(g.cov(r, c));
}

void write_arc(Writer& w, const Arc& arc) {
  w.u32(arc.from);
  w.u32(arc.to);
  write_gaussian(w, arc.pose);
  w.u32(arc.measurements);
}

void encode_payload(Writer& w, const HmtMap& map,
                    const std::vector<TopologicalHypothesis>& hypotheses,
                    const GridTable* grids = nullptr) {
  const std::vector<AreaId> ids = map.area_ids();
  w.count(ids.size(), "areas");
  for (AreaId id : ids) {
    const Area& a = map.area(id);
    w.u32(a.id);
    w.u32(a.frame.parent);
    w.pose(a.frame.origin_in_parent);
    w.u64(a.frame.created_step);
    w.f64(a.frame.created_time);
    write_keyframes(w, a.keyframes, "keyframes", "encode_topology");
    if (grids) {
      w.u32(a.map ? grids->at(a.map.get()) : kNoGrid);
    } else {
      w.u8(a.map ? 1 : 0);
      if (a.map) write_grid(w, *a.map);
    }
  }
  w.count(map.arcs().size(), "arcs");
  for (const auto& kv : map.arcs()) write_arc(w, kv.second);
  w.count(hypotheses.size(), "hypotheses");
  for (const TopologicalHypothesis& h : hypotheses) {
    validate(h, &map);
    w.f64(h.log_weight);
    w.count(h.path.size(), "path entries");
    for (const PathEntry& e : h.path) {
      w.u32(e.area);
      w.u64(e.step);
    }
  }
}

// ---------------------------------------------------------------- reading

// Bounds-checked reader over the inflated payload. The payload passed its
// checksum, so a failure here means a file written by something else (or a
// bug): the messages say what was being read.
class Reader {
 public:
  Reader(const std::string& bytes, const std::string& origin)
      : data_(bytes), origin_(origin) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw InputError("topology file '" + origin_ + "': inconsistent content: " +
                     what + " (at payload byte " + std::to_string(pos_) + ")");
  }
  void need(size_t n, const char* what) const {
    if (data_.size() - pos_ < n)
      fail(std::string("payload ends inside ") + what);
  }
  uint8_t u8(const char* what) {
    need(1, what);
    return static_cast<uint8_t>(data_[pos_++]);
  }
  uint32_t u32(const char* what) {
    need(4, what);
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<uint32_t>(static_cast<uint8_t>(data_[pos_++]))
           << (8 * i);
    return v;
  }
  uint64_t u64(const char* what) {
    need(8, what);
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i)
      v |= static_cast<uint64_t>(static_cast<uint8_t>(data_[pos_++]))
           << (8 * i);
    return v;
  }
  int32_t i32(const char* what) { return static_cast<int32_t>(u32(what)); }
  float f32(const char* what) {
    const uint32_t b = u32(what);
    float v;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }
  double f64(const char* what) {
    const uint64_t b = u64(what);
    double v;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }
  Pose2D pose(const char* what) {
    Pose2D p;
    p.x = f64(what);
    p.y = f64(what);
    p.theta = f64(what);
    return p;
  }
  // A count of items of at least `min_item_bytes` each: must fit in what is
  // left, so a bad count cannot ask for a huge allocation.
  size_t count(size_t min_item_bytes, const char* what) {
    const uint32_t n = u32(what);
    if (static_cast<uint64_t>(n) * min_item_bytes > data_.size() - pos_)
      fail(std::string("count of ") + what + " (" + std::to_string(n) +
           ") exceeds the remaining data");
    return n;
  }
  const char* take(size_t n, const char* what) {
    need(n, what);
    const char* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }
  bool at_end() const { return pos_ == data_.size(); }

 private:
  const std::string& data_;
  const std::string& origin_;
  size_t pos_ = 0;
};

bool finite(const Pose2D& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

std::shared_ptr<const grid::OccupancyGrid> read_grid(Reader& r, const std::string& where) {
  const double resolution = r.f64("map resolution");
  if (!(resolution > 0.0) || !std::isfinite(resolution))
    r.fail(where + ": resolution must be positive");
  auto g = std::make_shared<grid::OccupancyGrid>(resolution);
  const size_t tiles = r.count(8 + 4 * kCellsPerTile, "tiles");
  std::set<std::pair<int32_t, int32_t>> seen;
  int64_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  for (size_t t = 0; t < tiles; ++t) {
    const int32_t tx = r.i32("tile coordinates"),
                  ty = r.i32("tile coordinates");
    if (tx <= -kMaxTileCoord || tx >= kMaxTileCoord || ty <= -kMaxTileCoord ||
        ty >= kMaxTileCoord)
      r.fail(where + ": tile coordinates out of range");
    if (!seen.emplace(ty, tx).second)
      r.fail(where + ": a tile is stored twice");
    if (t == 0) {
      x0 = x1 = tx;
      y0 = y1 = ty;
    } else {
      x0 = std::min<int64_t>(x0, tx);
      x1 = std::max<int64_t>(x1, tx);
      y0 = std::min<int64_t>(y0, ty);
      y1 = std::max<int64_t>(y1, ty);
    }
    const int64_t n = static_cast<int64_t>(tiles);
    const int64_t accounted = std::max((n + kMaxTileGap) * (n + kMaxTileGap), n * kMaxSlotsPerTile);
    if ((x1 - x0 + 1) * (y1 - y0 + 1) > std::min(kMaxTileBoxArea, accounted))
      r.fail(where + ": tiles spread over an implausibly large area");
    const char* planes = r.take(4 * kCellsPerTile, "tile cells");
    grid::Tile& tile = g->mutable_tile(tx, ty);
    for (int i = 0; i < kCellsPerTile; ++i) {
      grid::Cell c;
      c.logodds = static_cast<grid::LogOdds>(static_cast<uint8_t>(planes[i]));
      c.hits = static_cast<uint8_t>(planes[kCellsPerTile + i]);
      c.hx = static_cast<int8_t>(
          static_cast<uint8_t>(planes[2 * kCellsPerTile + i]));
      c.hy = static_cast<int8_t>(
          static_cast<uint8_t>(planes[3 * kCellsPerTile + i]));
      tile.set(i, c);  // the hit plane only if some cell has hit statistics
    }
  }
  return g;
}

LaserScan read_scan(Reader& r) {
  LaserScan s;
  s.timestamp = r.f64("scan timestamp");
  s.angle_min = r.f32("scan angles");
  s.angle_increment = r.f32("scan angles");
  s.max_range = r.f32("scan maximum range");
  s.sensor_pose = r.pose("sensor pose");
  const size_t n = r.count(5, "beams");
  s.ranges.resize(n);
  for (size_t i = 0; i < n; ++i) s.ranges[i] = r.f32("ranges");
  const char* valid = r.take(n, "validity flags");
  s.valid.assign(reinterpret_cast<const uint8_t*>(valid),
                 reinterpret_cast<const uint8_t*>(valid) + n);
  return s;
}

// A list written by write_keyframes; `owner` ("area 3", "area graph")
// names it in errors. Files older than the keyframes' steps (`with_steps`
// false) give kUnknownStep.
std::vector<Keyframe> read_keyframes(Reader& r, const char* list, const std::string& owner,
                                     bool with_steps) {
  std::vector<Keyframe> out(r.count(24 + (with_steps ? 8 : 0) + 8 + 12 + 24 + 4, list));
  for (Keyframe& kf : out) {
    kf.pose = r.pose("keyframe pose");
    if (!finite(kf.pose)) r.fail(owner + ": non-finite keyframe pose");
    if (with_steps) kf.step = r.u64("keyframe step");
    kf.scan = read_scan(r);
  }
  return out;
}

// Reads a payload written by encode_payload (with the same grid table, if
// any) from r's position; the caller checks what follows.
PoseGaussian read_gaussian(Reader& r, const char* what) {
  PoseGaussian g;
  g.mean = r.pose(what);
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) g.cov(row, col) = r.f64(what);
  return g;
}

// An arc, checked on its own (whether its areas exist is the caller's
// check); `where` prefixes the error messages.
Arc read_arc(Reader& r, const std::string& where) {
  Arc arc;
  arc.from = r.u32("arc");
  arc.to = r.u32("arc");
  arc.pose = read_gaussian(r, "arc");
  arc.measurements = r.u32("arc");
  const std::string name =
      where + "arc " + std::to_string(arc.from) + "-" + std::to_string(arc.to);
  if (arc.from >= arc.to) r.fail(name + ": areas not in ascending order");
  if (!finite(arc.pose.mean) || std::abs(arc.pose.mean.theta) > M_PI)
    r.fail(name + ": mean is not a finite pose with its angle in [-pi, pi]");
  if (!is_positive_definite(arc.pose.cov))
    r.fail(name + ": covariance is not symmetric positive definite");
  if (arc.measurements < 1) r.fail(name + ": no measurements");
  return arc;
}

// `keyframe_steps`: the file's keyframes carry their steps (topology format
// 2, session format 5 and later).
TopologySnapshot decode_payload(
    Reader& r, bool keyframe_steps,
    const std::vector<std::shared_ptr<const grid::OccupancyGrid>>* grids = nullptr) {
  TopologySnapshot snap;
  HmtMap& map = snap.map;

  // Areas. Parents may be listed after their children (ids are the caller's
  // choice), so frames are checked once every area is known.
  const size_t areas = r.count(4 + 4 + 24 + 8 + 8 + 4 + 1, "areas");
  std::vector<std::pair<AreaId, ReferenceFrame>> frames;
  struct Pending {
    std::vector<Keyframe> keyframes;
    std::shared_ptr<const grid::OccupancyGrid> map;
  };
  std::vector<Pending> contents;
  for (size_t i = 0; i < areas; ++i) {
    const AreaId id = r.u32("area id");
    if (id == kNoArea) r.fail("an area has the reserved id 0xffffffff");
    if (!frames.empty() && id <= frames.back().first)
      r.fail("area ids are not strictly ascending (" + std::to_string(id) +
             " after " + std::to_string(frames.back().first) + ")");
    ReferenceFrame f;
    f.parent = r.u32("area frame");
    f.origin_in_parent = r.pose("area frame");
    f.created_step = r.u64("area frame");
    f.created_time = r.f64("area frame");
    if (!finite(f.origin_in_parent))
      r.fail("area " + std::to_string(id) + ": non-finite frame origin");
    frames.emplace_back(id, f);
    Pending p;
    p.keyframes = read_keyframes(r, "keyframes", "area " + std::to_string(id), keyframe_steps);
    if (grids) {
      const uint32_t g = r.u32("map index");
      if (g != kNoGrid && g >= grids->size())
        r.fail("area " + std::to_string(id) + ": map index " + std::to_string(g) +
               " beyond the " + std::to_string(grids->size()) + " maps stored");
      if (g != kNoGrid) p.map = (*grids)[g];
    } else {
      const uint8_t has_map = r.u8("map flag");
      if (has_map > 1) r.fail("area " + std::to_string(id) + ": bad map flag");
      if (has_map) p.map = read_grid(r, "map of area " + std::to_string(id));
    }
    contents.push_back(std::move(p));
  }
  std::set<AreaId> ids;
  for (const auto& kv : frames) ids.insert(kv.first);
  for (const auto& kv : frames)
    if (kv.second.parent != kNoArea &&
        (kv.second.parent == kv.first || !ids.count(kv.second.parent)))
      r.fail("area " + std::to_string(kv.first) + " has parent " +
             std::to_string(kv.second.parent) + ", which is not another area");
  // Insert parents before children: a root-first walk of the frame forest.
  {
    std::map<AreaId, size_t> index;
    for (size_t i = 0; i < frames.size(); ++i) index[frames[i].first] = i;
    std::vector<bool> added(frames.size(), false);
    size_t done = 0;
    while (done < frames.size()) {
      const size_t before = done;
      for (size_t i = 0; i < frames.size(); ++i) {
        if (added[i]) continue;
        const AreaId parent = frames[i].second.parent;
        if (parent != kNoArea && !added[index.at(parent)]) continue;
        map.add_area(frames[i].first, frames[i].second);
        for (auto& kf : contents[i].keyframes)
          map.add_keyframe(frames[i].first, std::move(kf));
        if (contents[i].map) map.set_map(frames[i].first, contents[i].map);
        added[i] = true;
        ++done;
      }
      if (done == before) r.fail("the areas' parents form a cycle");
    }
  }

  const size_t arcs = r.count(8 + 24 + 72 + 4, "arcs");
  std::pair<AreaId, AreaId> last{0, 0};
  for (size_t i = 0; i < arcs; ++i) {
    const Arc arc = read_arc(r, "");
    const std::string name =
        "arc " + std::to_string(arc.from) + "-" + std::to_string(arc.to);
    if (i > 0 && std::make_pair(arc.from, arc.to) <= last)
      r.fail(name + ": arcs not strictly ascending");
    last = {arc.from, arc.to};
    if (!map.has_area(arc.from) || !map.has_area(arc.to))
      r.fail(name + ": joins an area that does not exist");
    map.set_arc(arc);
  }

  const size_t hypotheses = r.count(8 + 4 + 12, "hypotheses");
  snap.hypotheses.reserve(hypotheses);
  for (size_t i = 0; i < hypotheses; ++i) {
    TopologicalHypothesis h;
    h.log_weight = r.f64("hypothesis weight");
    const size_t n = r.count(12, "path entries");
    h.path.reserve(n);
    for (size_t k = 0; k < n; ++k) {
      PathEntry e;
      e.area = r.u32("path entry");
      e.step = r.u64("path entry");
      h.path.push_back(e);
    }
    try {
      validate(h, &map);
    } catch (const std::invalid_argument& ex) {
      r.fail("hypothesis " + std::to_string(i) + ": " + ex.what());
    }
    snap.hypotheses.push_back(std::move(h));
  }
  return snap;
}

uint32_t get_u32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i)
    v |= static_cast<uint32_t>(static_cast<uint8_t>(b[at + i])) << (8 * i);
  return v;
}
uint64_t get_u64(const std::string& b, size_t at) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i)
    v |= static_cast<uint64_t>(static_cast<uint8_t>(b[at + i])) << (8 * i);
  return v;
}

// The file around a payload: header (magic, version, sizes, checksums) and
// the deflated payload. Shared by topology and session files.
std::string wrap(const char (&magic)[8], uint32_t version, Deflater& payload) {
  const uint64_t size = payload.size();
  const uint32_t crc = payload.crc();
  std::string stream = payload.finish();
  Writer h;
  h.bytes().assign(magic, sizeof magic);
  h.u32(version);
  h.u32(0);
  h.u64(size);
  h.u64(stream.size());
  h.u32(crc);
  h.u32(crc_of(h.bytes().data(), h.bytes().size()));
  return h.bytes() + stream;
}

// The payload of a file written by wrap(), after every check; `name` and
// `kind` say what the file is in error messages.
// Versions from oldest_version to version are read; *read_version (if
// given) gets the file's.
std::string unwrap(const std::string& bytes, const char (&magic)[8], uint32_t version,
                   const std::string& name, const char* kind, uint32_t oldest_version = 0,
                   uint32_t* read_version = nullptr) {
  if (bytes.empty()) throw InputError(name + " is empty");
  const size_t m = std::min(bytes.size(), sizeof magic);
  if (std::memcmp(bytes.data(), magic, m) != 0)
    throw InputError(name + " is not " + kind + " (bad magic)");
  if (bytes.size() < kTopologyHeaderSize)
    throw InputError(name + " is truncated: " + std::to_string(bytes.size()) +
                     " bytes, shorter than its " +
                     std::to_string(kTopologyHeaderSize) + "-byte header");
  const uint32_t found = get_u32(bytes, 8);
  if (oldest_version == 0) oldest_version = version;
  if (found < oldest_version || found > version)
    throw InputError(name + " has format version " + std::to_string(found) +
                     "; this build reads version " +
                     (oldest_version == version
                          ? std::to_string(version)
                          : std::to_string(oldest_version) + " to " + std::to_string(version)));
  if (read_version) *read_version = found;
  if (crc_of(bytes.data(), 36) != get_u32(bytes, 36))
    throw InputError(name + " is corrupt: header checksum mismatch");
  if (get_u32(bytes, 12) != 0)
    throw InputError(name + " uses unknown format flags");
  const uint64_t payload_size = get_u64(bytes, 16);
  const uint64_t stored = get_u64(bytes, 24);
  const uint64_t available = bytes.size() - kTopologyHeaderSize;
  if (available < stored)
    throw InputError(name + " is truncated: " + std::to_string(available) +
                     " of " + std::to_string(stored) + " bytes of map data");
  if (available > stored)
    throw InputError(name +
                     " is corrupt: " + std::to_string(available - stored) +
                     " unexpected bytes after the map data");
  if (payload_size > kMaxInflateRatio * stored + 64)
    throw InputError(name +
                     " is corrupt: its header claims an impossible size");

  std::string payload(payload_size, '\0');
  uLongf inflated = payload_size;
  const int rc = uncompress(
      reinterpret_cast<Bytef*>(payload.data()), &inflated,
      reinterpret_cast<const Bytef*>(bytes.data() + kTopologyHeaderSize),
      stored);
  if (rc != Z_OK || inflated != payload_size)
    throw InputError(name + " is corrupt: the map data does not inflate (" +
                     std::string(rc == Z_OK ? "wrong size" : zError(rc)) + ")");
  if (crc_of(payload.data(), payload.size()) != get_u32(bytes, 32))
    throw InputError(name + " is corrupt: map data checksum mismatch");
  return payload;
}

std::string read_whole_file(const std::string& path, const char* kind) {
  require_readable_file(path, kind);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)),
                    std::istreambuf_iterator<char>());
  if (in.bad())
    throw InputError(std::string(kind) + " '" + path + "' could not be read");
  return bytes;
}

void write_whole_file(const std::string& path, const std::string& bytes) {
  write_file_atomically(path, [&](std::ostream& os) {
    os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace

std::string encode_topology(
    const HmtMap& map, const std::vector<TopologicalHypothesis>& hypotheses) {
  Deflater d("encode_topology");
  Writer w(&d);
  encode_payload(w, map, hypotheses);
  w.flush();
  return wrap(kTopologyMagic, kTopologyFormatVersion, d);
}

TopologySnapshot decode_topology(const std::string& bytes,
                                 const std::string& origin) {
  uint32_t version = 0;
  const std::string payload =
      unwrap(bytes, kTopologyMagic, kTopologyFormatVersion, "topology file '" + origin + "'",
             "an HMT topology file", kOldestTopologyFormatVersion, &version);
  Reader r(payload, origin);
  TopologySnapshot snap = decode_payload(r, version >= 2);
  if (!r.at_end()) r.fail("unexpected data after the hypotheses");
  return snap;
}

void save_topology(const std::string& path, const HmtMap& map,
                   const std::vector<TopologicalHypothesis>& hypotheses) {
  write_whole_file(path, encode_topology(map, hypotheses));
}

TopologySnapshot load_topology(const std::string& path) {
  return decode_topology(read_whole_file(path, "topology file"), path);
}

// ------------------------------------------------------------------ session

namespace {

// A hypothesis's closures not yet accepted, each checked against its map.
std::vector<ClosureRecord> read_closures(Reader& r, const SessionHypothesis& h) {
  const std::string who = "hypothesis " + std::to_string(h.id) + ", closure ";
  std::vector<ClosureRecord> out(r.count(8 + 8 + 96 + 1, "pending closures"));
  for (size_t k = 0; k < out.size(); ++k) {
    ClosureRecord& c = out[k];
    const std::string name = who + std::to_string(k);
    c.from = r.u32("closure");
    c.to = r.u32("closure");
    c.step = r.u64("closure");
    c.measurement = read_gaussian(r, "closure measurement");
    if (c.from == c.to || !h.map.has_area(c.from) || !h.map.has_area(c.to))
      r.fail(name + ": " + std::to_string(c.from) + "-" + std::to_string(c.to) +
             " are not two areas of its map");
    if (!finite(c.measurement.mean) || std::abs(c.measurement.mean.theta) > M_PI)
      r.fail(name + ": measurement is not a finite pose with its angle in [-pi, pi]");
    if (!is_positive_definite(c.measurement.cov))
      r.fail(name + ": measurement covariance is not symmetric positive definite");
    const uint8_t has_arc = r.u8("closure");
    if (has_arc > 1) r.fail(name + ": bad arc flag");
    if (has_arc) {
      c.arc_before = read_arc(r, name + ": ");
      if (c.arc_before->from != std::min(c.from, c.to) ||
          c.arc_before->to != std::max(c.from, c.to))
        r.fail(name + ": its arc before joins other areas");
    }
  }
  return out;
}

}  // namespace

std::string encode_session(const Session& session) {
  // Every distinct area map once (hypotheses share the maps of the areas
  // they left before branching), in first-use order.
  GridTable table;
  std::vector<const grid::OccupancyGrid*> grids;
  for (const SessionHypothesis& h : session.hypotheses)
    for (AreaId id : h.map.area_ids())
      if (const auto& g = h.map.area(id).map)
        if (table.emplace(g.get(), static_cast<uint32_t>(grids.size())).second)
          grids.push_back(g.get());
  Deflater d("encode_session");
  Writer w(&d);
  w.u64(session.steps);
  w.f64(session.time);
  w.count(grids.size(), "maps");
  for (const grid::OccupancyGrid* g : grids) write_grid(w, *g);
  w.count(session.hypotheses.size(), "hypotheses");
  for (const SessionHypothesis& h : session.hypotheses) {
    w.u32(h.id);
    w.pose(h.robot);
    w.pose(h.aam_from_area);
    encode_payload(w, h.map, {h.topo}, &table);
    w.count(h.pending_closures.size(), "pending closures");
    for (const ClosureRecord& c : h.pending_closures) {
      w.u32(c.from);
      w.u32(c.to);
      w.u64(c.step);
      write_gaussian(w, c.measurement);
      w.u8(c.arc_before ? 1 : 0);
      if (c.arc_before) write_arc(w, *c.arc_before);
    }
    w.spill();
  }
  write_keyframes(w, session.area_graph, "area graph keyframes", "encode_session");
  w.flush();
  return wrap(kSessionMagic, kSessionFormatVersion, d);
}

Session decode_session(const std::string& bytes, const std::string& origin) {
  uint32_t version = 0;
  const std::string payload =
      unwrap(bytes, kSessionMagic, kSessionFormatVersion, "HMT map file '" + origin + "'",
             "an HMT map file", kOldestSessionFormatVersion, &version);
  Reader r(payload, origin);
  Session s;
  s.steps = r.u64("steps");
  s.time = r.f64("time");
  if (s.steps == 0) r.fail("no steps processed");
  std::vector<std::shared_ptr<const grid::OccupancyGrid>> grids(r.count(8 + 4, "maps"));
  for (size_t g = 0; g < grids.size(); ++g) grids[g] = read_grid(r, "map " + std::to_string(g));
  const size_t n = r.count(4 + 48 + 4, "hypotheses");
  if (n == 0) r.fail("no hypotheses");
  for (size_t i = 0; i < n; ++i) {
    SessionHypothesis h;
    h.id = r.u32("hypothesis id");
    if (i > 0 && h.id <= s.hypotheses.back().id) r.fail("hypothesis ids not ascending");
    h.robot = r.pose("robot pose");
    h.aam_from_area = r.pose("area abstraction frame");
    if (!finite(h.robot) || !finite(h.aam_from_area)) r.fail("a pose is not finite");
    TopologySnapshot t = decode_payload(r, version >= 5, &grids);
    if (t.hypotheses.size() != 1) r.fail("a hypothesis without exactly one path");
    h.map = std::move(t.map);
    h.topo = std::move(t.hypotheses[0]);
    if (!h.map.area(h.topo.current_area()).map)
      r.fail("hypothesis " + std::to_string(h.id) + ": its current area has no map");
    if (version >= 3) h.pending_closures = read_closures(r, h);
    s.hypotheses.push_back(std::move(h));
  }
  if (version >= 4)
    s.area_graph = read_keyframes(r, "area graph keyframes", "area graph", version >= 5);
  if (!r.at_end()) r.fail("unexpected data after the " + std::string(version >= 4 ? "area graph" : "hypotheses"));
  return s;
}

void save_session(const std::string& path, const Session& session) {
  write_whole_file(path, encode_session(session));
}

Session load_session(const std::string& path) {
  return decode_session(read_whole_file(path, "HMT map file"), path);
}

}  // namespace hmt::topology
