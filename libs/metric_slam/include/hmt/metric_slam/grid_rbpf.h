// Rao-Blackwellized particle filter for grid SLAM: each particle is a robot
// path hypothesis with the occupancy grid conditioned on it.
//
// Proposal (paper 002 Eq. 6, 12-13; Grisetti et al. 2007): for each particle
// the new scan is matched against the particle's own map starting from the
// odometry prediction; the target p(z|x,m) p(x|x',u) is evaluated on a small
// lattice around the match, a Gaussian is fitted to it and the new pose is
// drawn from that Gaussian; the weight is multiplied by the lattice estimate
// of the normaliser eta = integral of p(z|x,m) p(x|x',u) dx. When matching
// fails (too few beams explained) the particle falls back to the odometry
// proposal, weighted by the same lattice estimate around its sample; on a
// scan with too few beams to tell particles apart by their weights (open
// ground outdoors) it moves by the odometry without drawn noise
// (GridRbpf::move says why).
//
// Maps share unchanged tiles between particles (see grid::OccupancyGrid), so
// resampling and memory cost scale with what changed, not with map size.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <vector>

#include "hmt/common/random.h"
#include "hmt/common/sensor_data.h"
#include "hmt/grid/occupancy_grid.h"
#include "hmt/metric_slam/rbpf_options.h"
#include "hmt/metric_slam/scan_matcher.h"
#include "hmt/common/worker_pool.h"

namespace hmt::checkpoint {
struct Access;  // hmt/checkpoint/checkpoint.h
}  // namespace hmt::checkpoint

namespace hmt::metric_slam {

struct Particle {
  Pose2D pose;                 // current pose, in the current area's frame
  grid::OccupancyGrid map;     // the map conditioned on this path
  std::vector<Pose2D> path;    // one pose per step since the area began
  // The same steps as the outputs (trajectory, keyframe graph, global map)
  // estimate them: where the scan was matched, the proposal's mean (the best
  // estimate of that step given the path before it) rather than the drawn
  // pose, whose spread around it is sampling noise that no later step
  // removes (on Intel's consecutive scans 2 mm of a relation error of 28);
  // on a skipped step, the odometry's motion from the estimate before;
  // across a new area, the estimate seen from the new origin; on entering a
  // known area or a restart, the pose given. The filter runs on the draws.
  std::vector<Pose2D> estimates;
  double log_weight = 0.0;     // unnormalised, reset by resampling
  // Sum of the weight updates along the whole path, kept through resampling:
  // how well the path explained all its scans. It picks the best particle
  // (as GMapping does); the current weight alone only remembers the steps
  // since the last resampling, which with tempered weights is too little.
  double path_log_weight = 0.0;
  Pose2D last_insertion;       // pose of the last scan put into the map
  bool inserted = false;
};

struct RbpfStats {
  size_t steps = 0;               // scans given to process()
  size_t skipped_steps = 0;       // of which too little motion to filter
  size_t resamplings = 0;
  size_t particle_moves = 0;      // particle-steps filtered (a particle moved by a scan)
  size_t odometry_fallbacks = 0;  // of which matching failed
  // Particle moves that began at another particle's pose on the same map
  // (copies after a resampling, a new area or a closure's single pose):
  // the match and its lattice were the other's (GridRbpf::move()).
  size_t shared_starts = 0;
};

// A seed scan for a new area's map: the scan taken at `path_index` of the
// particles' current-area paths (one path entry per processed step).
struct SeedScan {
  size_t path_index = 0;
  const LaserScan* scan = nullptr;
};

// Copyable: a copy is an independent filter (maps share tiles until written)
// that shares the worker pool. Filters sharing a pool must not process()
// at the same time (the hybrid filter runs its hypotheses one after another).
class GridRbpf {
  // Checkpoints save and restore every member, bit for bit.
  friend struct hmt::checkpoint::Access;

 public:
  explicit GridRbpf(const RbpfOptions& opt);
  GridRbpf(const RbpfOptions& opt, std::shared_ptr<WorkerPool> pool);

  // One odometry increment followed by one scan. The first call initialises
  // every particle at the origin with the scan as its map. A scan taken
  // before the robot moved update_distance (less half the scan's own step)
  // or turned update_angle since the last filtered scan only extends the
  // paths by odometry.
  void process(const LogStep& step);

  // process() in three parts, so that one parallel loop can move the
  // particles of several filters (the hybrid filter's hypotheses) without a
  // barrier per filter: begin_step() does the bookkeeping and returns true
  // if the particles must move; then move(i) for every i < pending_moves(),
  // from any threads, each i once; then end_step() weighs and resamples.
  // The result is process()'s, whatever the order of the moves.
  //
  // A move is that of one group of particles that start from the same pose
  // on the same map (shared tiles): copies made by a resampling, or every
  // particle after a new area. Matching and the proposal's lattice depend
  // on nothing else, so the group computes them once; each particle still
  // draws its pose from its own random stream.
  bool begin_step(const LogStep& step);
  size_t pending_moves() const;
  void move(size_t i);
  void end_step();
  // log p(z_t | z^{t-1}, u^t) as this filter estimates it for the last
  // process() call: the log of the weighted mean of the particles' weight
  // updates (0 when the scan was skipped). Summed over steps it is the
  // (tempered) evidence of the data under this filter's map hypothesis,
  // which is how the hybrid filter weighs topological hypotheses.
  double last_log_evidence() const { return last_log_evidence_; }
  // The robot's pose error, in the current area's frame, that steps moved by
  // the odometry alone have added since the area began: steps whose scan has
  // too few beams for the weights to tell particles apart (nothing in
  // range, a blocked or failed laser, open ground), where the particles
  // follow the odometry without the motion model's noise (place()) and so
  // their spread does not grow. The motion model's covariance, propagated
  // along the best particle's path; zero where every step could weigh.
  // Whoever reads the particles' spread as the robot's uncertainty (the
  // hybrid filter's arcs and TSBI's priors) adds it, or a loop after a
  // blind stretch is searched for within centimetres of a pose metres off.
  const Eigen::Matrix3d& blind_cov() const { return blind_cov_; }
  // blind_cov() as it stood at each step of the current area: one entry per
  // entry of a particle's path (and estimates). Empty while no step since
  // the area began has been blind (all zero), as on most logs.
  const std::vector<Eigen::Matrix3d>& blind_trace() const { return blind_trace_; }
  // Restarts the random streams from `seed` (a copy that becomes a distinct
  // hypothesis draws its own numbers).
  void reseed(uint64_t seed);

  const std::vector<Particle>& particles() const { return particles_; }
  // The particle whose whole path explains the data best.
  size_t best_index() const;
  const Particle& best() const { return particles_[best_index()]; }
  // Normalised weights and their effective sample size.
  std::vector<double> weights() const;
  double ess() const;
  const RbpfStats& stats() const { return stats_; }
  const RbpfOptions& options() const { return opt_; }

  // --- What the hybrid metric-topological layers use ---
  // Enter a new area: every particle takes its current pose as the origin of
  // a fresh map, seeded with the last scan and the given earlier scans of
  // the current area, placed by the path of particle `seed_particle`
  // re-expressed in the new frame. All particles share the seeded map (one
  // map, not one per particle: the seeds' placement differs between
  // particles by centimetres, and a shared map costs no memory per
  // particle). Returns, per particle, the new origin expressed in the frame
  // of the area being left.
  std::vector<Pose2D> start_new_area(const std::vector<SeedScan>& seeds = {},
                                     size_t seed_particle = 0);
  // Re-enter a known area: every particle gets `map` (shared, not copied) and
  // the given pose in that map's frame (one per particle, or one for all).
  // `view_at`: the robot's pose now in that frame, as the match that chose
  // the area put it. Where the map cannot track the robot from there (the
  // last scan, placed at `view_at`, matches less of it than a particle's move
  // needs, [scan_matcher] min_match_ratio: a return at the edge of an area,
  // looking out of it), the last scan fills the cells the map never
  // observed, as it seeds a new area's map; otherwise the map is taken as
  // it is.
  void load_area(const grid::OccupancyGrid& map, const std::vector<Pose2D>& poses,
                 const Pose2D* view_at = nullptr);
  // Draws `n` particles from the current ones by their weights (systematic
  // resampling; weights equal afterwards): how a topological hypothesis's
  // share of the particle budget grows or shrinks. No-op when n is the
  // current count.
  void resize(size_t n);
  // Continue a saved run: every particle at `pose` in `map` (shared), equal
  // weights, as if the filter had just processed the saved run's last step.
  void restart(const grid::OccupancyGrid& map, const Pose2D& pose);

  // Bytes of the distinct map tiles held by all particles together.
  size_t map_memory_bytes() const;

 private:
  struct Lattice {
    bool ok = false;
    double log_eta = 0.0;      // log of the normaliser estimate
    Eigen::Vector3d mean;      // proposal Gaussian, relative to the centre
    Eigen::Matrix3d cov;
  };
  // The optimal-proposal target around `center` for a particle moving from
  // `from` by odometry `u` in `map`, headings `da` apart.
  // `pts` may be a subset of the scan; its log-likelihoods are multiplied by
  // `scale` to stand for the whole scan.
  Lattice evaluate_lattice(const grid::OccupancyGrid& map, const Pose2D& from,
                           const Pose2D& u, const ScanPoints& pts, double scale,
                           const Pose2D& center, double da) const;
  // The scan match `first` (from the odometry guess, scoring *score) and
  // the matches started at headings around the guess
  // ([metric_slam] heading_search_range): the one of highest likelihood x
  // motion prior, its score in *score.
  Pose2D search_headings(const Particle& p, const Pose2D& u, const MatchScan& scan,
                         const Pose2D& first, MatchScore* score) const;
  // The near-optimal proposal of a particle for the step under way: the
  // scan match and the Gaussian fitted on the lattice around it. Not `ok`
  // when the scan has no beams, does not match or the lattice fails; the
  // particle then moves by the odometry.
  struct Proposal {
    bool ok = false;
    Pose2D mode;
    Lattice lattice;
    Eigen::Matrix3d cov_factor;  // the lattice covariance's Cholesky factor L
  };
  Proposal propose(const Particle& p) const;
  // Moves particle i by `prop` (drawn from it, or by the odometry if not ok).
  void place(size_t i, const Proposal& prop);
  // end_step() of a step too few beams could weigh: the motion model's
  // error of the best particle's move, into blind_cov_.
  void add_blind_step();
  // blind_cov_ at the step just taken (its entry already on the paths),
  // onto blind_trace_.
  void record_blind();
  // blind_cov_ zero and the trace empty, where the paths restart at one
  // pose.
  void reset_blind();
  // Groups the particles that start from one pose on one map, into the
  // step under way's members and first.
  void group_same_starts();
  void initialise(const LogStep& step);
  void maybe_insert(Particle& p, const LaserScan& scan);
  // Whether the last scan at `pose` matches enough of `map` for a particle's
  // move ([scan_matcher] min_match_ratio of its beams).
  bool tracks_in(const grid::OccupancyGrid& map, const Pose2D& pose) const;
  void resample_if_needed();
  // Replaces the particles by `count` drawn from them by the weights `w`.
  void draw(const std::vector<double>& w, size_t count);

  // A step between begin_step() and end_step().
  struct Step {
    LogStep step;  // with the odometry accumulated since the last filtered scan
    // The scan's points, made ready for the matcher; the lattice's subset.
    std::optional<MatchScan> match;
    ScanPoints lattice_pts;
    double lattice_scale = 1.0;
    double sample_angular = 0.0;  // the lattice's heading spacing for this scan
    // Whether the scan has beams enough for its weights to tell particles
    // apart (GridRbpf::begin_step); a particle whose match fails on a scan
    // that cannot moves by the odometry alone.
    bool can_weigh = true;
    uint64_t seed = 0;            // the particles' streams derive from it
    // The particles in groups of the same start, each group's in order:
    // group g is members[first[g]] .. members[first[g + 1] - 1].
    std::vector<size_t> members, first;
    std::vector<char> fell_back;  // per particle: odometry proposal used
    std::vector<double> before;   // log weights before the step
  };

  RbpfOptions opt_;
  ScanMatcher matcher_;
  MotionModel motion_;
  Random rng_;  // resampling only; per-particle streams are derived per step
  std::shared_ptr<WorkerPool> pool_;
  std::vector<Particle> particles_;
  LaserScan last_scan_;
  Pose2D pending_motion_;  // odometry since the last filtered scan
  RbpfStats stats_;
  double last_log_evidence_ = 0.0;
  Eigen::Matrix3d blind_cov_ = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Matrix3d> blind_trace_;
  std::optional<Step> step_;  // between begin_step() and end_step()
};

}  // namespace hmt::metric_slam
