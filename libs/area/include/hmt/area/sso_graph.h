// The auxiliary graph of keyframes with SSO weights (001 Sec. III), grown one
// keyframe at a time (000 Eq. 21: one new row and column per keyframe) and
// kept sparse: only edges with SSO >= min_sso are stored, as adjacency lists;
// an Eigen sparse matrix is built on demand for the partition.
//
// Adding a keyframe must not cost one scan match per keyframe already in the
// graph, so the SSO is evaluated only where sensed regions can overlap:
//
// - Fixed-delta SSO (001 Eq. 16-18): every stored keyframe's points, in the
//   common frame, sit in one hash grid of 2*delta cells. The new keyframe's
//   points query it once; each hit within delta counts towards Pi(new, B) (at
//   most once per new point and B) and marks B's point as matched for
//   Pi(B, new). This computes the new row of W in a single pass whose cost is
//   the number of nearby points, i.e. independent of how many keyframes are
//   stored far away. It is exact: the same counts as scan_sso() on each pair
//   (both measure distances between the same two point sets, there in B's
//   frame, here in the common one).
//
// - Probabilistic SSO (000 Eq. 16): the covariances depend on the pair, so the
//   pairwise scan_sso() runs, but only against keyframes whose axis-aligned
//   bounding boxes (of the scan points in the common frame) overlap, each box
//   grown by the distance beyond which no point can pass the gate: to first
//   order the Mahalanobis test of a point pair is frame independent and its
//   covariance is the sum of the two points' covariances in the common frame,
//   so sqrt(gate * lambda_max) per keyframe bounds it; a factor 1.5 covers
//   the linearisation. Boxes are indexed in a coarse spatial hash
//   (index_cell_size).
//
// Keyframes are identified by caller-chosen integer ids; W rows follow the
// order of the ids passed to weight_matrix().
#pragma once

#include <cstdint>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/keyframe.h"
#include "hmt/area/ncut.h"
#include "hmt/area/scan_sso.h"
#include "hmt/area/sso_pair_cache.h"
#include "hmt/common/worker_pool.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::area {

class SsoGraph {
  // Checkpoints save and restore every member, bit for bit (but for the pair
  // cache and the keys that go with it, see use_pair_cache).
  friend struct hmt::checkpoint::Access;

 public:
  // `pool`: where a new keyframe's probabilistic pairs are evaluated (one
  // task per pair, joined in slot order, so the graph does not depend on
  // it); null evaluates them on the calling thread.
  explicit SsoGraph(const AreaOptions& options, std::shared_ptr<WorkerPool> pool = nullptr);
  // Probabilistic pairs are looked up in (and added to) `cache` before they
  // are computed: the same graph, with the pairs seen before not matched
  // again (sso_pair_cache.h). A cache is taken only by a graph whose every
  // keyframe was added with a cache attached (std::logic_error otherwise):
  // a node's key is taken when it is added. So a graph may go from one
  // cache to another (TSBI's area check: the area's keyframes' pairs in a
  // lasting cache, the latest scans' in one of the check's own). Null
  // detaches it, so that the pairs of keyframes added from then on, which
  // will not come back, do not fill it. Neither the cache nor the keys are
  // checkpointed state (a restored graph's keyframes have no keys).
  void use_pair_cache(std::shared_ptr<SsoPairCache> cache);

  // Adds the keyframe and its edges to every stored keyframe with SSO >=
  // min_sso. Throws std::invalid_argument if the id is already present.
  void add(int id, const Keyframe& keyframe);
  // Removes the keyframe and its edges; throws if absent.
  void remove(int id);
  bool contains(int id) const { return slot_of_.count(id) > 0; }
  size_t size() const { return slot_of_.size(); }
  // Stored ids, ascending.
  std::vector<int> ids() const;

  // (neighbour id, SSO) pairs of a stored keyframe, by neighbour id.
  std::vector<std::pair<int, double>> edges(int id) const;
  // SSO of a stored pair; 0 when no edge is stored.
  double weight(int a, int b) const;
  size_t num_edges() const { return num_edges_; }

  // Symmetric sparse W over `ids` (row k = ids[k]), zero diagonal; edges to
  // keyframes not listed are left out.
  WeightMatrix weight_matrix(const std::vector<int>& ids) const;

  // Keyframes whose SSO with the last added one was evaluated (probabilistic
  // mode: pairwise scan matches; fixed-delta: keyframes with a point near
  // one of its points). A measure of the work per keyframe.
  size_t last_candidates() const { return last_candidates_; }

  const AreaOptions& options() const { return options_; }

 private:
  struct Box {
    double x0, y0, x1, y1;
    bool intersects(const Box& o) const {
      return x0 <= o.x1 && o.x0 <= x1 && y0 <= o.y1 && o.y0 <= y1;
    }
  };
  struct Adj {
    int id;         // neighbour's id
    uint32_t slot;  // neighbour's slot
    double w;
  };
  struct Node {
    int id = -1;
    PoseGaussian pose;
    PreparedScan scan;            // robot frame (probabilistic pairs)
    uint64_t key = 0;             // keyframe_key(), with a pair cache
    bool keyed = false;           // `key` was set (added with a cache attached)
    std::vector<Point2D> global;  // scan points in the common frame
    Box box{0, 0, 0, 0};          // of `global`, grown by the reach
    std::vector<Adj> adj;
  };
  struct Entry {  // one point of a stored keyframe in the point index
    double x, y;
    uint32_t slot, idx;
  };

  void add_edge(uint32_t sa, uint32_t sb, double w);
  void compute_edges_fixed(uint32_t slot);
  void compute_edges_probabilistic(uint32_t slot);
  void index_points(uint32_t slot);
  void unindex_points(uint32_t slot);
  void index_box(uint32_t slot, bool insert);
  uint64_t point_key(double x, double y) const;
  const Node& node(int id) const;

  AreaOptions options_;
  std::shared_ptr<WorkerPool> pool_;  // null: pairs on the calling thread
  std::shared_ptr<SsoPairCache> cache_;  // null: every pair computed
  std::vector<Node> nodes_;  // by slot
  std::vector<uint32_t> free_slots_;
  std::unordered_map<int, uint32_t> slot_of_;
  size_t num_edges_ = 0;
  size_t last_candidates_ = 0;

  // Fixed-delta mode: points of all stored keyframes by 2*delta cell.
  double point_cell_ = 1.0;
  std::unordered_map<uint64_t, std::vector<Entry>> point_index_;
  // Probabilistic mode: slots by coarse cell of their box.
  std::unordered_map<uint64_t, std::vector<uint32_t>> box_index_;

  // Scratch for compute_edges_*, sized to the slot count.
  std::vector<int> last_point_;     // last new-point index that hit a slot
  std::vector<uint32_t> count_ab_;  // new points matched in slot
  std::vector<uint32_t> count_ba_;  // slot's points matched by new points
  std::vector<std::vector<char>> matched_b_;
  std::vector<uint32_t> touched_;
  std::vector<double> pair_sso_;  // probabilistic: SSO per candidate pair
};

}  // namespace hmt::area
