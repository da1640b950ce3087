#include "hmt/area/sso_graph.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace hmt::area {
namespace {

// Margin on the probabilistic reach for the error of the first-order bound
// (see the header).
constexpr double kReachSafety = 1.5;

}  // namespace

SsoGraph::SsoGraph(const AreaOptions& options, std::shared_ptr<WorkerPool> pool)
    : options_(options), pool_(std::move(pool)), point_cell_(2.0 * options.sso.delta) {
  options_.validate();
}

void SsoGraph::use_pair_cache(std::shared_ptr<SsoPairCache> cache) {
  if (cache)
    for (const auto& [id, slot] : slot_of_)
      if (!nodes_[slot].keyed)
        throw std::logic_error("SsoGraph::use_pair_cache: keyframe " + std::to_string(id) +
                               " was added without a cache (it has no key)");
  cache_ = std::move(cache);
}

uint64_t SsoGraph::point_key(double x, double y) const {
  return PointGrid::key(static_cast<int64_t>(std::floor(x / point_cell_)),
                        static_cast<int64_t>(std::floor(y / point_cell_)));
}

const SsoGraph::Node& SsoGraph::node(int id) const {
  const auto it = slot_of_.find(id);
  if (it == slot_of_.end())
    throw std::invalid_argument("SsoGraph: unknown keyframe id " +
                                std::to_string(id));
  return nodes_[it->second];
}

std::vector<int> SsoGraph::ids() const {
  std::vector<int> out;
  out.reserve(slot_of_.size());
  for (const auto& kv : slot_of_) out.push_back(kv.first);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<int, double>> SsoGraph::edges(int id) const {
  std::vector<std::pair<int, double>> out;
  for (const Adj& e : node(id).adj) out.emplace_back(e.id, e.w);
  std::sort(out.begin(), out.end());
  return out;
}

double SsoGraph::weight(int a, int b) const {
  for (const Adj& e : node(a).adj)
    if (e.id == b) return e.w;
  return 0.0;
}

void SsoGraph::add(int id, const Keyframe& kf) {
  if (slot_of_.count(id))
    throw std::invalid_argument("SsoGraph: keyframe id " + std::to_string(id) +
                                " added twice");
  uint32_t slot;
  if (!free_slots_.empty()) {
    slot = free_slots_.back();
    free_slots_.pop_back();
  } else {
    slot = static_cast<uint32_t>(nodes_.size());
    nodes_.emplace_back();
    last_point_.push_back(-1);
    count_ab_.push_back(0);
    count_ba_.push_back(0);
    matched_b_.emplace_back();
  }
  Node& n = nodes_[slot];
  n = Node{};
  n.id = id;
  n.pose = kf.pose;
  n.scan = PreparedScan(kf.scan, options_.sso);
  if (cache_) {
    n.key = keyframe_key(kf, options_.sso);
    n.keyed = true;
  }
  n.global.reserve(n.scan.size());
  for (const Point2D& p : n.scan.points())
    n.global.push_back(kf.pose.mean.transform(p));

  double reach = 0.0;
  if (options_.sso.use_probabilistic) {
    double lmax = 0.0;
    for (size_t i = 0; i < n.scan.size(); ++i)
      lmax = std::max(
          lmax, max_eigenvalue(compose_point_cov(kf.pose, n.scan.points()[i],
                                                 n.scan.point_covs()[i])));
    reach =
        kReachSafety * std::sqrt(options_.sso.gate * (lmax + kVarianceFloor));
  }
  if (!n.global.empty()) {
    Box b{std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max(),
          std::numeric_limits<double>::lowest(),
          std::numeric_limits<double>::lowest()};
    for (const Point2D& p : n.global) {
      b.x0 = std::min(b.x0, p.x);
      b.y0 = std::min(b.y0, p.y);
      b.x1 = std::max(b.x1, p.x);
      b.y1 = std::max(b.y1, p.y);
    }
    n.box = {b.x0 - reach, b.y0 - reach, b.x1 + reach, b.y1 + reach};
  }
  slot_of_[id] = slot;

  last_candidates_ = 0;
  if (n.global.empty()) return;  // senses nothing: no edges, nothing to index
  if (options_.sso.use_probabilistic) {
    compute_edges_probabilistic(slot);
    index_box(slot, true);
  } else {
    compute_edges_fixed(slot);
    index_points(slot);
  }
}

void SsoGraph::add_edge(uint32_t sa, uint32_t sb, double w) {
  if (!(w > 0.0) || w < options_.min_sso) return;
  // Adjacency lists stay sorted by id, so that weight_matrix() can write
  // columns without sorting. Ids usually grow, making this an append.
  const auto insert = [](std::vector<Adj>& adj, const Adj& e) {
    auto pos = adj.end();
    while (pos != adj.begin() && (pos - 1)->id > e.id) --pos;
    adj.insert(pos, e);
  };
  insert(nodes_[sa].adj, {nodes_[sb].id, sb, w});
  insert(nodes_[sb].adj, {nodes_[sa].id, sa, w});
  ++num_edges_;
}

void SsoGraph::compute_edges_fixed(uint32_t slot) {
  const Node& a = nodes_[slot];
  const double delta = options_.sso.delta;
  const double d2 = delta * delta;
  touched_.clear();
  const int na = static_cast<int>(a.global.size());
  for (int i = 0; i < na; ++i) {
    const Point2D& p = a.global[i];
    const int64_t x0 =
        static_cast<int64_t>(std::floor((p.x - delta) / point_cell_));
    const int64_t x1 =
        static_cast<int64_t>(std::floor((p.x + delta) / point_cell_));
    const int64_t y0 =
        static_cast<int64_t>(std::floor((p.y - delta) / point_cell_));
    const int64_t y1 =
        static_cast<int64_t>(std::floor((p.y + delta) / point_cell_));
    for (int64_t ix = x0; ix <= x1; ++ix) {
      for (int64_t iy = y0; iy <= y1; ++iy) {
        const auto it = point_index_.find(PointGrid::key(ix, iy));
        if (it == point_index_.end()) continue;
        for (const Entry& e : it->second) {
          const double dx = e.x - p.x, dy = e.y - p.y;
          if (dx * dx + dy * dy > d2) continue;
          const uint32_t s = e.slot;
          if (last_point_[s] < 0) {  // first hit on this keyframe
            touched_.push_back(s);
            matched_b_[s].assign(nodes_[s].global.size(), 0);
          }
          if (last_point_[s] != i) {
            last_point_[s] = i;
            ++count_ab_[s];
          }
          if (!matched_b_[s][e.idx]) {
            matched_b_[s][e.idx] = 1;
            ++count_ba_[s];
          }
        }
      }
    }
  }
  last_candidates_ = touched_.size();
  for (const uint32_t s : touched_) {
    const double w =
        0.5 * (static_cast<double>(count_ab_[s]) / na +
               static_cast<double>(count_ba_[s]) / nodes_[s].global.size());
    add_edge(slot, s, w);
    last_point_[s] = -1;
    count_ab_[s] = count_ba_[s] = 0;
    matched_b_[s].clear();
  }
}

void SsoGraph::compute_edges_probabilistic(uint32_t slot) {
  const Node& a = nodes_[slot];
  const double c = options_.index_cell_size;
  touched_.clear();
  const int64_t x0 = static_cast<int64_t>(std::floor(a.box.x0 / c));
  const int64_t x1 = static_cast<int64_t>(std::floor(a.box.x1 / c));
  const int64_t y0 = static_cast<int64_t>(std::floor(a.box.y0 / c));
  const int64_t y1 = static_cast<int64_t>(std::floor(a.box.y1 / c));
  for (int64_t ix = x0; ix <= x1; ++ix) {
    for (int64_t iy = y0; iy <= y1; ++iy) {
      const auto it = box_index_.find(PointGrid::key(ix, iy));
      if (it == box_index_.end()) continue;
      for (const uint32_t s : it->second) {
        if (last_point_[s] >= 0) continue;  // already a candidate
        last_point_[s] = 0;
        touched_.push_back(s);
      }
    }
  }
  // Ascending slot order: the same pairs in the same order whatever the hash.
  std::sort(touched_.begin(), touched_.end());
  for (const uint32_t s : touched_) last_point_[s] = -1;
  touched_.erase(std::remove_if(touched_.begin(), touched_.end(),
                                [&](uint32_t s) { return !a.box.intersects(nodes_[s].box); }),
                 touched_.end());
  last_candidates_ = touched_.size();
  // The pairs are independent scan matches, the bulk of the partitioner's
  // time where the scans reach far (each point's gate grows with range):
  // evaluated on the pool, each into its own slot, and joined in slot order.
  pair_sso_.assign(touched_.size(), 0.0);
  const auto evaluate = [&](size_t k) {
    const Node& b = nodes_[touched_[k]];
    if (cache_) {
      if (const std::optional<double> v = cache_->find(a.key, b.key)) {
        pair_sso_[k] = *v;
        return;
      }
    }
    pair_sso_[k] = scan_sso(a.scan, a.pose, b.scan, b.pose, options_.sso);
    if (cache_) cache_->put(a.key, b.key, pair_sso_[k]);
  };
  if (pool_ && touched_.size() > 1) {
    pool_->parallel_for(touched_.size(), evaluate);
  } else {
    for (size_t k = 0; k < touched_.size(); ++k) evaluate(k);
  }
  for (size_t k = 0; k < touched_.size(); ++k) add_edge(slot, touched_[k], pair_sso_[k]);
}

void SsoGraph::index_points(uint32_t slot) {
  const Node& n = nodes_[slot];
  for (uint32_t i = 0; i < n.global.size(); ++i) {
    const Point2D& p = n.global[i];
    point_index_[point_key(p.x, p.y)].push_back({p.x, p.y, slot, i});
  }
}

void SsoGraph::unindex_points(uint32_t slot) {
  const Node& n = nodes_[slot];
  std::vector<uint64_t> keys;
  keys.reserve(n.global.size());
  for (const Point2D& p : n.global) keys.push_back(point_key(p.x, p.y));
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  for (const uint64_t k : keys) {
    auto it = point_index_.find(k);
    if (it == point_index_.end()) continue;
    auto& v = it->second;
    v.erase(std::remove_if(v.begin(), v.end(),
                           [slot](const Entry& e) { return e.slot == slot; }),
            v.end());
    if (v.empty()) point_index_.erase(it);
  }
}

void SsoGraph::index_box(uint32_t slot, bool insert) {
  const Box& b = nodes_[slot].box;
  const double c = options_.index_cell_size;
  const int64_t x0 = static_cast<int64_t>(std::floor(b.x0 / c));
  const int64_t x1 = static_cast<int64_t>(std::floor(b.x1 / c));
  const int64_t y0 = static_cast<int64_t>(std::floor(b.y0 / c));
  const int64_t y1 = static_cast<int64_t>(std::floor(b.y1 / c));
  for (int64_t ix = x0; ix <= x1; ++ix) {
    for (int64_t iy = y0; iy <= y1; ++iy) {
      const uint64_t k = PointGrid::key(ix, iy);
      if (insert) {
        box_index_[k].push_back(slot);
        continue;
      }
      auto it = box_index_.find(k);
      if (it == box_index_.end()) continue;
      auto& v = it->second;
      v.erase(std::remove(v.begin(), v.end(), slot), v.end());
      if (v.empty()) box_index_.erase(it);
    }
  }
}

void SsoGraph::remove(int id) {
  const auto it = slot_of_.find(id);
  if (it == slot_of_.end())
    throw std::invalid_argument("SsoGraph: removing unknown keyframe id " +
                                std::to_string(id));
  const uint32_t slot = it->second;
  Node& n = nodes_[slot];
  for (const Adj& e : n.adj) {
    auto& adj = nodes_[e.slot].adj;
    for (size_t k = 0; k < adj.size(); ++k) {
      if (adj[k].slot == slot) {
        adj.erase(adj.begin() + k);  // keeps the id order
        break;
      }
    }
    --num_edges_;
  }
  if (!n.global.empty()) {
    if (options_.sso.use_probabilistic)
      index_box(slot, false);
    else
      unindex_points(slot);
  }
  n = Node{};
  slot_of_.erase(it);
  free_slots_.push_back(slot);
}

WeightMatrix SsoGraph::weight_matrix(const std::vector<int>& ids) const {
  std::vector<int> local(nodes_.size(), -1);
  std::vector<uint32_t> slots(ids.size());
  for (size_t k = 0; k < ids.size(); ++k) {
    const auto it = slot_of_.find(ids[k]);
    if (it == slot_of_.end())
      throw std::invalid_argument("SsoGraph::weight_matrix: unknown id " +
                                  std::to_string(ids[k]));
    if (local[it->second] >= 0)
      throw std::invalid_argument("SsoGraph::weight_matrix: repeated id " +
                                  std::to_string(ids[k]));
    local[it->second] = static_cast<int>(k);
    slots[k] = it->second;
  }
  // Compressed columns written directly into Eigen's arrays (this runs for
  // every online update). Adjacency lists are sorted by id, so with ids
  // ascending the rows of each column come out sorted too.
  const Eigen::Index n = static_cast<Eigen::Index>(ids.size());
  Eigen::Index nnz = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    for (const Adj& e : nodes_[slots[k]].adj) nnz += local[e.slot] >= 0;
  WeightMatrix W(n, n);
  W.resizeNonZeros(nnz);
  int* outer = W.outerIndexPtr();
  int* inner = W.innerIndexPtr();
  double* value = W.valuePtr();
  const bool ascending = std::is_sorted(ids.begin(), ids.end());
  std::vector<std::pair<int, double>> col;
  Eigen::Index p = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    outer[k] = static_cast<int>(p);
    col.clear();
    for (const Adj& e : nodes_[slots[k]].adj)
      if (local[e.slot] >= 0) col.emplace_back(local[e.slot], e.w);
    if (!ascending) std::sort(col.begin(), col.end());
    for (const auto& [j, w] : col) {
      inner[p] = j;
      value[p] = w;
      ++p;
    }
  }
  outer[n] = static_cast<int>(p);
  return W;
}

}  // namespace hmt::area
