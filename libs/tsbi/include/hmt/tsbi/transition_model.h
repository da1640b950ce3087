// The topological transition model of HMT-SLAM (002 Sec. IV-A), evaluated
// when the area abstraction says the robot entered a new area, once for each
// group of particles that shares a topological path (a hypothesis).
//
// Outcomes: "an unexplored area", with the constant eta, and "the known area
// gamma again" (a loop closure) for every area other than the current one,
// with
//     F(gamma) = E_{x ~ prior_gamma} [ p(z | x, m_gamma) / p(z | nothing) ]
// the expected likelihood of the latest observations z in gamma's stored map
// over the prior of the robot pose in gamma's frame. The prior comes from the
// arcs: the robot pose in the current area c composed with the Gaussians along
// the Dijkstra path from gamma to c (Eq. 15, topology/shortest_paths.h).
// Where c and gamma also share an arc of their own and the path contradicts
// it, the prior is widened to hold both (candidate_frame() below).
// The probabilities are eta and the F(gamma), normalised.
//
// How F is computed. p(z|x,m) is the likelihood field model the metric filter
// weighs its particles with (metric_slam::ScanMatcher, tempered by the same
// likelihood_gain, so the outcome probabilities and the later evidence live
// on one scale). Dividing by p(z | nothing) -- every point at the field's
// truncation distance -- makes the integrand 1 where the map explains
// nothing. The modes of the integrand are found by grid matching from a set
// of starts spread over the prior (the 3 principal axes at -k, 0, +k standard
// deviations); around each mode x* the log-likelihood is taken quadratic,
// with the scan matcher's Gauss-Newton information H (Laplace), and the
// Gaussian integral is closed:
//   int exp(l(x) - l0) N(x; mu, S) dx
//     ~ exp(l(x*) - l0) |I + H S|^-1/2 exp(-1/2 e^T H (I + S H)^-1 e),
//   e = x* - mu,
// which stays finite when H is singular (a corridor leaves the pose free
// along it; then the prior alone decides there). The factor |I + H S|^-1/2
// is the Occam factor: a broad prior (a long loop) needs a better match. F
// sums the distinct modes that explain at least min_match_ratio of the points
// within the area's extent (the bounds of the cells its map observed: the
// points beyond it are seen from where the map never reached, and say
// nothing for or against the area) and min_points_explained of all of them,
// and lie inside the prior's gate; areas with none are not candidates. When
// the prior is much wider than the matcher's basin (after a long loop), the
// starts also include the best distinct maxima of a wide search over the
// whole gate: by default an exact branch and bound over a lattice as fine
// as the grid (bnb_matcher.h), so that a return is not missed because the
// prior is wide; or a lattice coarsened to a fixed number of poses.
//
// The area check. Areas overlap: what the robot sees just after leaving an
// area is still partly in that area's map, and in its predecessor's. The
// area abstraction has just said the latest observations form an area of
// their own; a known area is therefore only a candidate if, placed at the
// mode, those observations would not be cut off from the area's keyframes
// by the same criterion (Ncut({latest}, {area}) >= tau, with the same SSO).
// A true return passes (the latest scans overlap the area's as much as its
// own do); a neighbour seen across the border does not.
//
// What it costs, and what is skipped. Most known areas cannot explain the
// latest observations anywhere in their prior (they lie elsewhere in the
// building, or only overlap it at the border). Before matching, a branch
// and bound on the area's obstacle raster (match_field.h) proves, for most
// of them, that no pose in the prior's gate lets min_points_explained of
// the points reach an obstacle: no mode could pass the ratio gate, so the area
// is not a candidate -- the answer the full evaluation would give, without
// the matching. The wide search scores its poses on the same raster (one
// lookup per point), the branch and bound on a stack of min-filtered
// rasters of it (cost_stack.h). Rasters are built once per archived map
// and kept while a hypothesis holds the map (the stacks, larger, only up
// to a byte budget, the least recently used dropped first; a dropped
// stack is rebuilt when needed, to the same bytes); the candidates' matcher
// starts run in one
// parallel loop on the worker pool (each alone, their modes summed in start
// order, so the result does not depend on the threads).
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/sso_pair_cache.h"
#include "hmt/metric_slam/scan_matcher.h"
#include "hmt/metric_slam/scan_points.h"
#include "hmt/common/worker_pool.h"
#include "hmt/topology/hmt_map.h"
#include "hmt/topology/pose_gaussian.h"
#include "hmt/topology/shortest_paths.h"
#include "hmt/tsbi/cost_stack.h"
#include "hmt/tsbi/match_field.h"
#include "hmt/tsbi/observations.h"
#include "hmt/tsbi/tsbi_options.h"

namespace hmt::tsbi {

struct Outcome {
  topology::AreaId area = topology::kNoArea;  // kNoArea: an unexplored area
  double log_f = 0.0;        // log eta, or log F(gamma)
  double probability = 0.0;  // normalised over the outcomes returned
  // Loop closures only:
  topology::PoseGaussian prior;  // robot pose in the area's frame, from the arcs
  topology::PoseGaussian robot;  // the best mode, with the Laplace covariance
  double match_ratio = 0.0;      // points explained at the best mode
  int modes = 0;                 // distinct modes that entered F
  bool is_new() const { return area == topology::kNoArea; }
};

// What became of one known area at a new-area event: every area with a map
// that the arcs reach from the current one is weighed or ruled out for a
// reason, and the reasons say why a loop did or did not close
// (tsbi_candidates.csv).
struct CandidateReport {
  enum class Verdict : uint8_t {
    kOutOfReach,  // its map's box (or its empty map) is beyond the
                  // observations' reach from the prior's gate
    kBound,       // not searched: no pose in the gate lets
                  // min_points_explained of the points reach an obstacle
                  // (may_reach_ratio), or
                  // there were no observations
    kNoMode,      // searched: no match inside the prior's gate passed
                  // the ratio gate
    kImprobable,  // F below min_probability times eta: never an outcome
    kAreaCheck,   // the best mode failed the area check (same_area)
    kOutcome,     // an outcome of the event
  };
  topology::AreaId area = topology::kNoArea;
  // The prior of the robot's pose in the area's frame, from the arcs: its
  // mean and standard deviations (kept for every area of every event, so
  // not the whole covariance).
  Pose2D prior_mean;
  Eigen::Vector3d prior_sd = Eigen::Vector3d::Zero();
  Verdict verdict = Verdict::kOutOfReach;
  bool wide = false;     // the prior was searched as a whole (wide search)
  uint32_t starts = 0;   // matcher starts (0: not searched)
  double best_ratio = 0.0;  // most points any start's match explained
  double log_f = 0.0;       // log F, where a mode passed the gates (has_log_f)
  bool has_log_f() const {
    return verdict == Verdict::kImprobable || verdict == Verdict::kAreaCheck ||
           verdict == Verdict::kOutcome;
  }
};
// The verdict's name in tsbi_candidates.csv.
const char* verdict_name(CandidateReport::Verdict v);

// F(gamma) of one area map for a given prior. Returns false (no candidate)
// when no mode passes the gates.
struct ExpectedLikelihood {
  bool candidate = false;
  double log_f = 0.0;
  topology::PoseGaussian robot;
  double match_ratio = 0.0;
  int modes = 0;
};

class TransitionModel {
 public:
  // `likelihood_gain` divides log-likelihoods, as in the metric filter;
  // `area` gives the SSO and tau of the area check; `pool`, if any, weighs
  // the candidate areas in parallel.
  TransitionModel(const TsbiOptions& options,
                  const metric_slam::MatcherOptions& matcher,
                  double likelihood_gain, const area::AreaOptions& area,
                  std::shared_ptr<WorkerPool> pool = nullptr);

  // The outcomes for a hypothesis whose map is `map`, whose robot is in area
  // `current` at `robot` (in that area's frame) and has just made the
  // observations `obs` (points in the robot frame). The new-area outcome
  // comes first, known areas (the candidates) follow in ascending id; the
  // probabilities sum to 1. Not const: it keeps the areas' match fields.
  // `considered`, if given, receives a report of every known area with a
  // map that the arcs reach, in ascending id.
  std::vector<Outcome> evaluate(const topology::HmtMap& map,
                                topology::AreaId current,
                                const topology::PoseGaussian& robot,
                                const Observations& obs,
                                std::vector<CandidateReport>* considered = nullptr);

  // One hypothesis's question at a new-area event: evaluate()'s arguments.
  struct Query {
    const topology::HmtMap* map = nullptr;
    topology::AreaId current = topology::kNoArea;
    topology::PoseGaussian robot;
    const Observations* observations = nullptr;
  };
  // evaluate() for every hypothesis of one event at once: out[i] and
  // (*considered)[i] are what evaluate() gives for queries[i], to the bit.
  // The candidate areas of all the queries are one set of tasks on the
  // pool, so that a hypothesis with one costly candidate (a wide search,
  // an area check) does not leave a thread idle while the next waits: with
  // rival hypotheses, each asks about the same few look-alike areas.
  std::vector<std::vector<Outcome>> evaluate_all(
      const std::vector<Query>& queries,
      std::vector<std::vector<CandidateReport>>* considered = nullptr);

  ExpectedLikelihood expected_likelihood(const grid::OccupancyGrid& map,
                                         const topology::PoseGaussian& prior,
                                         const Observations& obs) const;

  const TsbiOptions& options() const { return opt_; }
  // Match fields held (for tests and memory accounting).
  size_t cached_fields() const { return fields_.size(); }
  size_t cached_field_bytes() const;
  // Cost stacks held, and their bytes.
  size_t cached_stacks() const { return stacks_.size(); }
  size_t cached_stack_bytes() const;

 private:
  // The known areas the observations can reach from the prior's gate, each
  // with its prior (robot pose in the area's frame, from the arcs); those
  // beyond reach into `out_of_reach`, if given.
  std::vector<Outcome> reachable_areas(const topology::HmtMap& map,
                                       topology::AreaId current,
                                       const topology::PoseGaussian& robot,
                                       const Observations& obs,
                                       std::vector<CandidateReport>* out_of_reach) const;
  // The match field of each map: from the cache, or built (in parallel)
  // and cached. Fields of maps no hypothesis holds are dropped.
  std::vector<std::shared_ptr<const MatchField>> fields_for(
      const std::vector<std::shared_ptr<const grid::OccupancyGrid>>& maps);
  // The cost stack of `map`'s match field `field`: from the cache, or built
  // and cached. Thread-safe: each searching thread asks for its own area's.
  std::shared_ptr<const CostStack> stack_for(const grid::OccupancyGrid* map,
                                             const std::shared_ptr<const MatchField>& field);
  // Drops the cached stacks of maps whose fields went, then the least
  // recently used beyond the budget (never one a search holds). Under
  // stacks_mutex_.
  void trim_stacks();
  std::shared_ptr<const CostStack> make_stack(const MatchField& field) const;
  // F(gamma) in three steps, so that evaluate() can run the matcher
  // starts of every candidate area in one parallel loop (an event often
  // has a single candidate, whose 27+ starts would otherwise run on one
  // thread): the search's set-up (the widened prior, the gates, the starts;
  // no starts when a gate already rules the area out; then, for a wide
  // prior, the wide search's maxima), one match per start, and the modes'
  // Laplace sum in start order.
  struct Search {
    topology::PoseGaussian prior;  // widened by prior_std_*
    Eigen::Matrix3d prior_inverse = Eigen::Matrix3d::Identity();
    double scale = 0.0;           // log-likelihood tempering
    double l0 = 0.0;              // log-likelihood of an empty map
    std::vector<Pose2D> starts;
    bool wide = false;  // the prior is wide: add_wide_starts() is due
  };
  struct Match {
    Pose2D pose;
    metric_slam::MatchScore score;
    Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
    size_t in_extent = 0;  // points within the bounds of the cells the map observed
    size_t contradicted = 0;  // points on surfaces in the map's clear free space
  };
  Search prepare_search(const grid::OccupancyGrid& map, const MatchField& field,
                        const topology::PoseGaussian& prior, const Observations& obs) const;
  // The wide search's maxima, after the prior mean's start. `stack`: the
  // field's cost stack (the branch and bound only).
  void add_wide_starts(Search* search, const MatchField& field, const CostStack* stack,
                       const Observations& obs) const;
  // The match from `start` of the observations, `ready` their points made
  // ready for the matcher (once for all of a query's starts).
  Match match_from(const grid::OccupancyGrid& map, const Pose2D& start, const Observations& obs,
                   const metric_slam::MatchScan& ready) const;
  // The ratio gate: the match explains min_match_ratio of its points within
  // the known area's extent (a matched point may lie up to the matcher's
  // window outside it).
  bool explains_extent(const Match& m) const;
  ExpectedLikelihood sum_modes(const Search& search, const std::vector<Match>& matches,
                               const Observations& obs) const;
  ExpectedLikelihood expected_likelihood(const grid::OccupancyGrid& map,
                                         const MatchField& field,
                                         const topology::PoseGaussian& prior,
                                         const Observations& obs) const;
  // The best-scoring poses of a lattice over the prior's gate.
  std::vector<Pose2D> wide_search(const MatchField& field,
                                  const topology::PoseGaussian& prior,
                                  const metric_slam::ScanPoints& obs) const;
  // The best distinct maxima of every pose of the branch and bound's
  // lattice in the gate.
  std::vector<Pose2D> bnb_search(const CostStack& stack, const MatchField& field,
                                 const topology::PoseGaussian& prior,
                                 const metric_slam::ScanPoints& obs) const;
  // The area check of TsbiOptions::area_check, with the robot at `robot` in
  // the area's frame.
  bool same_area(const topology::Area& area, const Pose2D& robot,
                 const Observations& obs) const;
  // fn(i) for i in [0, n), on the pool if there is one.
  void for_each_index(size_t n, const std::function<void(size_t)>& fn) const;

  TsbiOptions opt_;
  metric_slam::ScanMatcher matcher_;
  grid::LogOdds free_threshold_;  // scaled_logit(free_probability)
  double gain_;
  area::AreaOptions area_;
  std::shared_ptr<WorkerPool> pool_;
  // The area check's keyframe pairs, which come back event after event
  // (sso_pair_cache.h); it changes no result.
  std::shared_ptr<area::SsoPairCache> area_check_pairs_ = std::make_shared<area::SsoPairCache>();
  // Match fields by map. The entry holds the map too, so that its address
  // cannot be reused by another map while the entry lives.
  struct CachedField {
    std::shared_ptr<const grid::OccupancyGrid> map;
    std::shared_ptr<const MatchField> field;
    uint64_t used = 0;  // the fields_for() call that last used it
  };
  std::map<const grid::OccupancyGrid*, CachedField> fields_;
  uint64_t field_calls_ = 0;
  // Cost stacks by map, each with the field it was built from (a stack
  // whose map's field went or was replaced goes too; holding the field,
  // not the map, it does not keep the map alive) and the event that last
  // used it; the least recently used go first beyond the budget.
  struct CachedStack {
    std::shared_ptr<const MatchField> field;
    std::shared_ptr<const CostStack> stack;
    uint64_t used = 0;  // the stack_for() call that last used it
  };
  std::map<const grid::OccupancyGrid*, CachedStack> stacks_;
  uint64_t stack_calls_ = 0;  // stack_for() calls, the stacks' `used` clock
  mutable std::mutex stacks_mutex_;
};

// Where area `id`'s frame lies seen from area `current`, as TSBI's prior
// composes it: the pose `tree` (Dijkstra from `current`) gives it along the
// most certain path. Where `current` and `id` also share an arc of their own
// and that path is another way round, the two are checked against each
// other: when the arc's mean lies outside the path's gate (options.gate, on
// both covariances with the prior's floors prior_std_xy and
// prior_std_theta), the arcs of that loop contradict each other, and the
// covariance is widened by the disagreement d, cov + d d^T, as TLCA widens an
// inconsistent closure (tlca/acceptance.h), so that the gate holds both.
// Why: each loop arc is a fine alignment that claims millimetres and a
// milliradian, and which of them is wrong is not known. On the Infinite
// Corridor driven twice, three such arcs formed a loop 0.53 m off (0.018
// rad over a 28 m arc); the second lap's prior, through the way round, put
// the place where the first lap had matched the area outside the gate, and
// the lap made a new area there instead of returning.
topology::PoseGaussian candidate_frame(const topology::HmtMap& map,
                                       const topology::PathTree& tree,
                                       topology::AreaId current, topology::AreaId id,
                                       const TsbiOptions& options);

// The evidence of an event, log(sum over the outcomes of F(gamma) / eta):
// how much better the hypothesis's known areas explain the observations
// than an unexplored area alone would (0 when only "new" is left).
double log_evidence(const std::vector<Outcome>& outcomes, double log_eta);

// The outcomes worth following: indices of those with probability >=
// min_probability (the most probable one if none is).
std::vector<size_t> probable_outcomes(const std::vector<Outcome>& outcomes,
                                      double min_probability);

}  // namespace hmt::tsbi
