// Every member of the run's state, through cereal. One `io` per type, used
// both ways (cereal's archives are symmetric); the few types without a
// default constructor or with a raw-memory form are read and written by
// hand. Shared pointers (copy-on-write map tiles, area maps, stored areas,
// keyframe scans, finished trajectory segments) are tracked by cereal: each
// object is written once and shared again on load.
#include "state_io.h"

#include <cereal/types/array.hpp>
#include <cereal/types/map.hpp>
#include <cereal/types/memory.hpp>
#include <cereal/types/optional.hpp>
#include <cereal/types/string.hpp>
#include <cereal/types/unordered_map.hpp>
#include <cereal/types/utility.hpp>
#include <cereal/types/vector.hpp>
#include <Eigen/Core>
#include <algorithm>
#include <sstream>
#include <type_traits>

#include "hmt/checkpoint/checkpoint.h"
#include "hmt/common/error.h"

namespace hmt::checkpoint {
namespace {

template <class A>
constexpr bool kLoading = A::is_loading::value;

// Values whose bytes are the value: trivially copyable types, and Eigen's
// fixed-size matrices (plain arrays of scalars behind a user-written copy).
template <class T>
struct IsPlain : std::is_trivially_copyable<T> {};
template <class S, int R, int C, int O, int MR, int MC>
struct IsPlain<Eigen::Matrix<S, R, C, O, MR, MC>>
    : std::bool_constant<(R > 0 && C > 0 && std::is_arithmetic_v<S>)> {};

// A vector of plain values (no pointers, no padding read back as meaning)
// as its size and its bytes.
template <class A, class T>
void pod_vector(A& ar, std::vector<T>& v) {
  static_assert(IsPlain<T>::value);
  cereal::size_type n = v.size();
  ar(cereal::make_size_tag(n));
  if constexpr (kLoading<A>) v.resize(static_cast<size_t>(n));
  if (n > 0) ar(cereal::binary_data(v.data(), static_cast<size_t>(n) * sizeof(T)));
}

template <class A, class T>
void pod(A& ar, T& v) {
  static_assert(IsPlain<T>::value);
  ar(cereal::binary_data(&v, sizeof(T)));
}

// A hash map as its entries in key order: the same map gives the same bytes
// whatever its insertion history (its buckets' order is not part of its
// meaning: these maps are only looked up, never iterated).
template <class A, class M, class F>
void hash_map(A& ar, M& m, F&& value_io) {
  cereal::size_type n = m.size();
  ar(cereal::make_size_tag(n));
  if constexpr (kLoading<A>) {
    m.clear();
    m.reserve(static_cast<size_t>(n));
    for (cereal::size_type i = 0; i < n; ++i) {
      typename M::key_type key{};
      ar(key);
      value_io(m[key]);
    }
  } else {
    std::vector<typename M::key_type> keys;
    keys.reserve(m.size());
    for (const auto& kv : m) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end());
    for (auto key : keys) {
      ar(key);
      value_io(m.at(key));
    }
  }
}

}  // namespace

// Friend of every class whose private state a checkpoint holds.
struct Access {
  template <class A>
  static void io(A& ar, Random& r) {
    std::string engine;
    if constexpr (!kLoading<A>) {
      std::ostringstream os;
      os << r.engine_;
      engine = os.str();
    }
    ar(engine, r.has_spare_, r.spare_);
    if constexpr (kLoading<A>) {
      std::istringstream is(engine);
      is >> r.engine_;
      if (!is) throw InputError("a random generator's state does not parse");
    }
  }

  template <class A>
  static void io(A& ar, grid::Tile& t) {
    ar(cereal::binary_data(t.logodds.data(), sizeof(t.logodds)));
    bool hits = t.hit_means != nullptr;
    ar(hits);
    if constexpr (kLoading<A>) t.hit_means = hits ? std::make_unique<grid::Tile::HitPlane>() : nullptr;
    if (hits) ar(cereal::binary_data(t.hit_means->data(), sizeof(grid::Tile::HitPlane)));
  }

  template <class A>
  static void io(A& ar, grid::OccupancyGrid& g) {
    ar(g.resolution_, g.inv_resolution_, g.tx0_, g.ty0_, g.ntx_, g.nty_, g.tiles_);
    if constexpr (kLoading<A>)
      if (g.tiles_.size() != static_cast<size_t>(g.ntx_) * static_cast<size_t>(g.nty_))
        throw InputError("a map's tile table does not match its size");
  }

  template <class A>
  static void io(A& ar, topology::HmtMap& m) {
    ar(m.areas_, m.arcs_);
  }

  template <class A>
  static void io(A& ar, metric_slam::GridRbpf& f) {
    if constexpr (!kLoading<A>)
      if (f.step_) throw Error(ExitCode::kInternal, "checkpoint in the middle of a metric step");
    // The seed too: each hypothesis reseeds its copy (GridRbpf::reseed).
    ar(f.opt_.seed, f.rng_, f.particles_, f.last_scan_, f.pending_motion_, f.stats_,
       f.last_log_evidence_, f.blind_cov_, f.blind_trace_);
  }

  template <class A>
  static void io(A& ar, area::PointGrid& g) {
    ar(g.cell_, g.inv_cell_);
    pod_vector(ar, g.pts_);
    pod_vector(ar, g.idx_);
    pod_vector(ar, g.cells_);
    pod_vector(ar, g.table_);
    ar(g.mask_);
    // The bounds follow from the cells: derived, not stored.
    if constexpr (kLoading<A>) g.set_bounds();
  }

  template <class A>
  static void io(A& ar, area::PreparedScan& s) {
    pod_vector(ar, s.points_);
    pod_vector(ar, s.ranges_);
    pod_vector(ar, s.covs_);
    ar(s.max_var_, s.var_floor_, s.var_per_range2_);
    pod(ar, s.origin_);
    io(ar, s.grid_);
  }

  template <class A>
  static void io(A& ar, area::SsoGraph& g) {
    cereal::size_type n = g.nodes_.size();
    ar(cereal::make_size_tag(n));
    if constexpr (kLoading<A>) g.nodes_.resize(static_cast<size_t>(n));
    for (auto& node : g.nodes_) {
      ar(node.id, node.pose);
      io(ar, node.scan);
      pod_vector(ar, node.global);
      pod(ar, node.box);
      pod_vector(ar, node.adj);
    }
    ar(g.free_slots_);
    hash_map(ar, g.slot_of_, [&](uint32_t& slot) { ar(slot); });
    ar(g.num_edges_, g.last_candidates_, g.point_cell_);
    hash_map(ar, g.point_index_, [&](auto& entries) { pod_vector(ar, entries); });
    hash_map(ar, g.box_index_, [&](std::vector<uint32_t>& slots) { pod_vector(ar, slots); });
    ar(g.last_point_, g.count_ab_, g.count_ba_, g.matched_b_, g.touched_);
  }

  template <class A>
  static void io(A& ar, area::OnlinePartitioner& p) {
    io(ar, p.graph_);
    ar(p.area_, p.window_, p.next_id_, p.newest_uncertainty_, p.newest_distinctiveness_);
  }

  template <class A>
  static void io(A& ar, hybrid::Hypothesis& h) {
    ar(h.id, h.filter, h.map, h.topo, h.area_start_step, h.aam_from_area, h.keyframes_from_aam,
       h.trajectory, h.pending_closures);
  }

  template <class A>
  static void io(A& ar, hybrid::HybridFilter& f) {
    io(ar, f.aam_);
    cereal::size_type n = f.hyps_.size();
    ar(cereal::make_size_tag(n));
    if constexpr (kLoading<A>) {
      // Each hypothesis's particles run on the filter's own worker pool.
      f.hyps_.clear();
      for (cereal::size_type i = 0; i < n; ++i) {
        hybrid::Hypothesis h{metric_slam::GridRbpf(f.opt_.rbpf, f.pool_)};
        io(ar, h);
        f.hyps_.push_back(std::move(h));
      }
    } else {
      for (auto& h : f.hyps_) io(ar, h);
    }
    cereal::size_type k = f.keyframes_.size();
    ar(cereal::make_size_tag(k));
    if constexpr (kLoading<A>) f.keyframes_.resize(static_cast<size_t>(k));
    for (auto& kf : f.keyframes_) ar(kf.step, kf.scan, kf.pose);
    ar(f.next_hypothesis_id_, f.has_keyframe_, f.last_keyframe_pose_, f.step_, f.time_,
       f.transitions_, f.acceptances_, f.accepted_path_, f.stats_);
  }

  template <class A>
  static void io(A& ar, framework::HmtSystem& s) {
    if constexpr (!kLoading<A>)
      if (s.aam_outstanding_ != 0 || s.event_in_flight_ || s.alignments_outstanding_ != 0 ||
          !s.waiting_decisions_.empty())
        throw Error(ExitCode::kInternal, "checkpoint while a process still has work out");
    io(ar, s.filter_);
    io(ar, s.partitioner_);
    ar(s.traces_, s.times_, s.fed_, s.event_applied_step_);
    framework::AreaSummary& a = s.area_layer_.summary_;
    ar(a.keyframes, a.new_area_decisions, a.last_decision_step);
  }
};

}  // namespace hmt::checkpoint

// ------------------------------------------------------------------------
// cereal finds these by argument-dependent lookup.

namespace Eigen {
template <class A, class S, int R, int C, int O, int MR, int MC>
void serialize(A& ar, Matrix<S, R, C, O, MR, MC>& m) {
  static_assert(R > 0 && C > 0, "fixed-size matrices only");
  ar(cereal::binary_data(m.data(), sizeof(S) * R * C));
}
}  // namespace Eigen

namespace hmt {
template <class A>
void serialize(A& ar, Pose2D& p) {
  ar(p.x, p.y, p.theta);
}
template <class A>
void serialize(A& ar, Point2D& p) {
  ar(p.x, p.y);
}
template <class A>
void serialize(A& ar, PoseGaussian& g) {
  ar(g.mean, g.cov);
}
template <class A>
void serialize(A& ar, LaserScan& s) {
  ar(s.timestamp, s.angle_min, s.angle_increment, s.max_range, s.ranges, s.valid,
     s.sensor_pose);
}
template <class A>
void serialize(A& ar, Random& r) {
  checkpoint::Access::io(ar, r);
}
}  // namespace hmt

namespace hmt::grid {
template <class A>
void serialize(A& ar, Tile& t) {
  checkpoint::Access::io(ar, t);
}
template <class A>
void serialize(A& ar, OccupancyGrid& g) {
  checkpoint::Access::io(ar, g);
}
}  // namespace hmt::grid

namespace hmt::topology {
template <class A>
void serialize(A& ar, Keyframe& k) {
  ar(k.pose, k.scan, k.step);
}
template <class A>
void serialize(A& ar, ReferenceFrame& f) {
  ar(f.parent, f.origin_in_parent, f.created_step, f.created_time);
}
template <class A>
void serialize(A& ar, Area& a) {
  ar(a.id, a.frame, a.keyframes, a.map);
}
template <class A>
void serialize(A& ar, Arc& a) {
  ar(a.from, a.to, a.pose, a.measurements);
}
template <class A>
void serialize(A& ar, HmtMap& m) {
  checkpoint::Access::io(ar, m);
}
template <class A>
void serialize(A& ar, PathEntry& e) {
  ar(e.area, e.step);
}
template <class A>
void serialize(A& ar, TopologicalHypothesis& h) {
  ar(h.path, h.log_weight);
}
template <class A>
void serialize(A& ar, ClosureRecord& c) {
  ar(c.from, c.to, c.step, c.arc_before, c.measurement);
}
}  // namespace hmt::topology

namespace hmt::metric_slam {
template <class A>
void serialize(A& ar, Particle& p) {
  ar(p.pose, p.map, p.path, p.estimates, p.log_weight, p.path_log_weight, p.last_insertion,
     p.inserted);
}
template <class A>
void serialize(A& ar, RbpfStats& s) {
  ar(s.steps, s.skipped_steps, s.resamplings, s.particle_moves, s.odometry_fallbacks,
     s.shared_starts);
}
template <class A>
void serialize(A& ar, GridRbpf& f) {
  checkpoint::Access::io(ar, f);
}
}  // namespace hmt::metric_slam

namespace hmt::tsbi {
template <class A>
void serialize(A& ar, Outcome& o) {
  ar(o.area, o.log_f, o.probability, o.prior, o.robot, o.match_ratio, o.modes);
}
template <class A>
void serialize(A& ar, CandidateReport& r) {
  ar(r.area, r.prior_mean, r.prior_sd, r.verdict, r.wide, r.starts, r.best_ratio, r.log_f);
}
}  // namespace hmt::tsbi

namespace hmt::tlca {
template <class A>
void serialize(A& ar, ClosureReport& c) {
  ar(c.record, c.aligned, c.consistent, c.reason, c.used, c.correction_m, c.correction_rad,
     c.inlier_ratio, c.overlap_points, c.loop_hops, c.loop_chi2);
}
}  // namespace hmt::tlca

namespace hmt::hybrid {
template <class A>
void serialize(A& ar, TrajectorySegment& s) {
  ar(s.area, s.first_step, s.poses, s.blind);
}
template <class A>
void serialize(A& ar, TransitionEvent& e) {
  ar(e.step, e.time, e.hypothesis, e.parent_probability, e.from_area, e.outcomes, e.considered,
     e.children, e.entered, e.observed_points, e.candidate_maps);
}
template <class A>
void serialize(A& ar, AcceptanceEvent& e) {
  ar(e.step, e.hypothesis, e.probability, e.dropped, e.closures);
}
template <class A>
void serialize(A& ar, HybridStats& s) {
  ar(s.steps, s.keyframes, s.new_area_events, s.loop_closures_accepted, s.max_hypotheses_alive,
     s.forgotten_path_entries);
}
}  // namespace hmt::hybrid

namespace hmt::framework {
template <class A>
void serialize(A& ar, HypothesisTrace& t) {
  ar(t.id, t.probability, t.area, t.ess, t.particles);
}
template <class A>
void serialize(A& ar, StepTrace& t) {
  ar(t.step, t.time, t.pmf, t.hypotheses, t.areas, t.map_memory_bytes, t.peak_rss_bytes);
}
template <class A>
void serialize(A& ar, ProcessTimes& t) {
  ar(t.metric_slam, t.aam, t.tsbi, t.tlca);
}
}  // namespace hmt::framework

// Last: every serialize above is visible where the templates are instantiated.
namespace hmt::checkpoint {

void write_state(cereal::BinaryOutputArchive& ar, const framework::HmtSystem& system) {
  // cereal writes through non-const references; nothing here modifies.
  Access::io(ar, const_cast<framework::HmtSystem&>(system));
}

void read_state(cereal::BinaryInputArchive& ar, framework::HmtSystem& system) {
  Access::io(ar, system);
}

}  // namespace hmt::checkpoint
