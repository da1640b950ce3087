#include "hmt/metric_slam/grid_rbpf.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "hmt/common/error.h"
#include "hmt/common/log_sum_exp.h"
#include "hmt/common/pose_gaussian.h"
#include "hmt/grid/scan_insertion.h"
#include "nearest_spacing.h"

namespace hmt::metric_slam {

GridRbpf::GridRbpf(const RbpfOptions& opt)
    : GridRbpf(opt, std::make_shared<WorkerPool>(WorkerPool::threads_for(opt.threads))) {}

GridRbpf::GridRbpf(const RbpfOptions& opt, std::shared_ptr<WorkerPool> pool)
    : opt_(opt),
      matcher_(opt.matcher),
      motion_(opt.motion),
      rng_(opt.seed),
      pool_(std::move(pool)) {
  if (!pool_) throw Error(ExitCode::kInternal, "GridRbpf: no worker pool");
}

void GridRbpf::reseed(uint64_t seed) {
  opt_.seed = seed;
  rng_ = Random(seed);
}

void GridRbpf::initialise(const LogStep& step) {
  Particle p;
  p.map = grid::OccupancyGrid(opt_.resolution);
  grid::insert_scan(p.map, p.pose, step.scan, opt_.insertion);
  p.inserted = true;
  p.last_insertion = p.pose;
  p.path.push_back(p.pose);
  p.estimates.push_back(p.pose);
  // Every particle starts from the same map: the copies share its tiles.
  particles_.assign(static_cast<size_t>(opt_.particles), p);
  reset_blind();
}

void GridRbpf::maybe_insert(Particle& p, const LaserScan& scan) {
  if (p.inserted && within_spacing(p.pose - p.last_insertion, opt_.map_update_distance,
                                   opt_.map_update_angle))
    return;
  grid::insert_scan(p.map, p.pose, scan, opt_.insertion);
  p.last_insertion = p.pose;
  p.inserted = true;
}

GridRbpf::Lattice GridRbpf::evaluate_lattice(const grid::OccupancyGrid& map,
                                             const Pose2D& from, const Pose2D& u,
                                             const ScanPoints& pts, double scale,
                                             const Pose2D& center, double da) const {
  // Target p(z|x,m) p(x|x',u) on a 3x3x3 lattice around `center`. Two
  // temperings of the same evaluations: a mild one shapes the proposal (a
  // pose must follow the scan closely), a strong one weights the particles
  // (neighbouring beams are correlated; the plain product would make every
  // resampling keep a single survivor).
  const MotionSigmas sg = motion_.sigmas(u);
  const double log_norm_motion =
      -1.5 * std::log(2 * M_PI) - 2 * std::log(sg.xy) - std::log(sg.theta);
  const double dl = opt_.sample_linear;
  std::array<double, 27> logq, logw;
  std::array<Eigen::Vector3d, 27> offs;
  size_t j = 0;
  for (int a = -1; a <= 1; ++a) {
    // The nine translations of one heading are scored together.
    Pose2D poses[9];
    for (int y = -1, t = 0; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x, ++t)
        poses[t] = Pose2D(center.x + x * dl, center.y + y * dl, wrap_angle(center.theta + a * da));
    MatchScore scores[9];
    matcher_.score_same_heading(map, poses, 9, pts, scores);
    for (int y = -1, t = 0; y <= 1; ++y)
      for (int x = -1; x <= 1; ++x, ++t, ++j) {
        const double ll = scale * scores[t].log_likelihood;
        const double lm = log_norm_motion + motion_.log_density(from, u, poses[t]);
        logq[j] = ll / opt_.proposal_gain + lm;
        logw[j] = ll / opt_.likelihood_gain + lm;
        offs[j] = Eigen::Vector3d(x * dl, y * dl, a * da);
      }
  }
  Lattice out;
  const double log_q = log_sum_exp({logq.begin(), logq.end()});
  // eta = sum_j tau_j * (lattice cell volume)
  out.log_eta = log_sum_exp({logw.begin(), logw.end()}) + std::log(dl * dl * da);
  out.ok = std::isfinite(log_q) && std::isfinite(out.log_eta);
  if (!out.ok) return out;
  out.mean.setZero();
  out.cov.setZero();
  for (j = 0; j < 27; ++j) out.mean += std::exp(logq[j] - log_q) * offs[j];
  for (j = 0; j < 27; ++j) {
    const Eigen::Vector3d d = offs[j] - out.mean;
    out.cov += std::exp(logq[j] - log_q) * d * d.transpose();
  }
  // The lattice cannot resolve spreads much below its spacing; keep the
  // Gaussian at least that wide so sampling stays well-posed.
  out.cov.diagonal() += Eigen::Vector3d(1e-3 * dl * dl, 1e-3 * dl * dl, 1e-3 * da * da);
  return out;
}

void GridRbpf::process(const LogStep& input) {
  if (!begin_step(input)) return;
  pool_->parallel_for(pending_moves(), [&](size_t i) { move(i); });
  end_step();
}

bool GridRbpf::begin_step(const LogStep& input) {
  if (step_) throw Error(ExitCode::kInternal, "GridRbpf::begin_step before end_step");
  last_log_evidence_ = 0.0;
  if (particles_.empty()) {
    last_scan_ = input.scan;
    initialise(input);
    ++stats_.steps;
    return false;
  }
  // Filter only once the robot has moved enough since the last update: a
  // scan from (nearly) the same place adds little, and a robot standing
  // still must not make the filter resample on nothing. Skipped scans get
  // the dead-reckoned pose in each particle's path. The scan filtered is
  // the one nearest the spacing (nearest_spacing.h).
  const Pose2D& u = input.odometry_increment;
  pending_motion_ = pending_motion_ + u;
  ++stats_.steps;
  if (short_of_nearest_mark(pending_motion_, u, opt_.update_distance, opt_.update_angle)) {
    for (auto& p : particles_) {
      p.path.push_back(p.pose + pending_motion_);
      p.estimates.push_back(p.estimates.back() + u);
    }
    record_blind();
    ++stats_.skipped_steps;
    return false;
  }
  Step& st = step_.emplace();
  st.step = input;
  st.step.odometry_increment = pending_motion_;
  pending_motion_ = Pose2D();
  last_scan_ = st.step.scan;
  st.match.emplace(prepare_scan(st.step.scan, opt_.matcher.max_range, opt_.matcher.beam_skip,
                                opt_.resolution),
                   opt_.matcher);
  const ScanPoints& pts = st.match->points();
  // The lattice evaluates 27 poses per particle: it uses an evenly spread
  // subset of the beams, its log-likelihoods scaled back to the full count.
  st.lattice_pts = spread_subset(pts, opt_.lattice_beams);
  st.lattice_scale = st.lattice_pts.hit.empty()
                         ? 1.0
                         : static_cast<double>(pts.hit.size()) / st.lattice_pts.hit.size();
  st.seed = mix_seed(opt_.seed ^ mix_seed(stats_.steps));
  // Where the match's heading basin is narrower than the hill climbing's
  // steps (far returns only, outdoors), it is narrower than the lattice's
  // heading spacing too: the outer headings then put every far point outside
  // the match window, the Gaussian collapses onto the match's heading and
  // the sampled pose keeps whatever heading error the match left. There the
  // lattice's headings are one basin (of the fine window) apart.
  st.sample_angular = opt_.sample_angular;
  const double far = st.match->far();
  if (matcher_.steps_over_heading_basin(far, opt_.resolution))
    st.sample_angular = std::min(
        st.sample_angular, ScanMatcher::heading_basin(far, opt_.matcher.window, opt_.resolution));
  // The most the scan can change one particle's weight against another's:
  // every beam on an obstacle for one, none for the other. Below e the
  // weights cannot pick among poses the motion model draws (27 beams by
  // default: 1.125 nats a beam, tempered by likelihood_gain 30). Indoor
  // scans hold hundreds of beams within 20 m; outdoors, open ground leaves
  // a handful within the matching range.
  st.can_weigh = static_cast<double>(pts.hit.size()) *
                     matcher_.unmatched_beam_cost(opt_.resolution) >=
                 opt_.likelihood_gain;
  st.fell_back.assign(particles_.size(), 0);
  st.before.resize(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i) st.before[i] = particles_[i].log_weight;
  group_same_starts();
  stats_.shared_starts += particles_.size() - pending_moves();
  return true;
}

namespace {
// The same pose to the bit (-0 and +0 apart: the match must see the very
// numbers the other particle's saw).
bool same_bits(const Pose2D& a, const Pose2D& b) {
  return std::memcmp(&a.x, &b.x, sizeof a.x) == 0 && std::memcmp(&a.y, &b.y, sizeof a.y) == 0 &&
         std::memcmp(&a.theta, &b.theta, sizeof a.theta) == 0;
}
}  // namespace

void GridRbpf::group_same_starts() {
  Step& st = *step_;
  const size_t n = particles_.size();
  // group_of[i]: the group particle i joins, numbered by first member.
  std::vector<size_t> group_of(n), leaders;
  for (size_t i = 0; i < n; ++i) {
    const Particle& p = particles_[i];
    size_t g = 0;
    while (g < leaders.size() &&
           !(same_bits(particles_[leaders[g]].pose, p.pose) &&
             particles_[leaders[g]].map.shares_every_tile_with(p.map)))
      ++g;
    if (g == leaders.size()) leaders.push_back(i);
    group_of[i] = g;
  }
  st.first.assign(leaders.size() + 1, 0);
  for (size_t i = 0; i < n; ++i) ++st.first[group_of[i] + 1];
  for (size_t g = 0; g < leaders.size(); ++g) st.first[g + 1] += st.first[g];
  st.members.resize(n);
  std::vector<size_t> next(st.first.begin(), st.first.end() - 1);
  for (size_t i = 0; i < n; ++i) st.members[next[group_of[i]]++] = i;
}

size_t GridRbpf::pending_moves() const { return step_ ? step_->first.size() - 1 : 0; }

Pose2D GridRbpf::search_headings(const Particle& p, const Pose2D& u, const MatchScan& scan,
                                 const Pose2D& first, MatchScore* score) const {
  const double step = 2.0 * opt_.matcher.angular_step;
  if (!(opt_.heading_search_range >= step) || !(step > 0)) return first;
  const Pose2D guess = p.pose + u;
  // The target of the optimal proposal is p(z|x,m) p(x|x',u): its mode, not
  // the likelihood's alone, decides between the starts.
  auto target = [&](const Pose2D& x, const MatchScore& s) {
    return s.log_likelihood / opt_.proposal_gain + motion_.log_density(p.pose, u, x);
  };
  Pose2D best = first;
  double best_target = target(first, *score);
  const int k_max = static_cast<int>(std::floor(opt_.heading_search_range / step + 1e-9));
  for (int k = 1; k <= k_max; ++k)
    for (int sign : {1, -1}) {
      const Pose2D start(guess.x, guess.y, wrap_angle(guess.theta + sign * k * step));
      MatchScore s;
      // As far off in position as the first start (propose()).
      const Pose2D m =
          matcher_.optimize(p.map, start, scan, &s, nullptr, motion_.distance_sigma(u));
      // A restart that climbs back to within one search step of the first
      // match found the same basin, refined: the hill climbing's own steps
      // settle that. Only another basin (a turn the odometry got wrong)
      // replaces it. Outdoors (the Malaga log) such refinements scored a few
      // more far-range beams at a heading 0.04-0.06 rad off, and bent the map.
      if (std::fabs(wrap_angle(m.theta - first.theta)) <= step) continue;
      const double t = target(m, s);
      if (t > best_target) {
        best = m;
        best_target = t;
        *score = s;
      }
    }
  return best;
}

void GridRbpf::move(size_t g) {
  const Step& st = *step_;
  const size_t begin = st.first.at(g), end = st.first.at(g + 1);
  // The group's particles share pose and map: one proposal serves them all.
  const Proposal prop = propose(particles_[st.members[begin]]);
  for (size_t k = begin; k < end; ++k) place(st.members[k], prop);
}

GridRbpf::Proposal GridRbpf::propose(const Particle& p) const {
  const Step& st = *step_;
  const Pose2D& u = st.step.odometry_increment;
  const size_t n = st.match->points().hit.size();
  Proposal out;
  if (opt_.proposal != ProposalKind::kOptimal || n == 0) return out;
  MatchScore ms;
  // The match reaches as far as the step may have carried the robot off its
  // odometry: the motion model's sigma for the distance (one sigma of a
  // model wide on purpose, place()). Beyond the climb's own reach only: a
  // step of 2.4 m or more at the defaults.
  out.mode =
      matcher_.optimize(p.map, p.pose + u, *st.match, &ms, nullptr, motion_.distance_sigma(u));
  // A scan with too few beams to weigh particles by cannot tell heading
  // basins apart either: a restart that lands one or two more far points
  // on some tree wins the untempered target, and the particle turns by a
  // tenth of a radian on no evidence.
  if (st.can_weigh && ms.matched < opt_.heading_search_ratio * static_cast<double>(n))
    out.mode = search_headings(p, u, *st.match, out.mode, &ms);
  if (!opt_.matcher.tracks(ms.matched, n)) return out;
  out.lattice = evaluate_lattice(p.map, p.pose, u, st.lattice_pts, st.lattice_scale, out.mode,
                                 st.sample_angular);
  out.ok = out.lattice.ok;
  if (out.ok) out.cov_factor = out.lattice.cov.llt().matrixL();
  return out;
}

void GridRbpf::place(size_t i, const Proposal& prop) {
  Step& st = *step_;
  Particle& p = particles_[i];
  Random rng(mix_seed(st.seed ^ (i * 0x632be59bd9b4e019ULL)));
  const Pose2D& u = st.step.odometry_increment;
  const bool fallback = !prop.ok;
  Pose2D estimate;  // the proposal's mean, where the scan was matched

  if (!fallback) {
    const Lattice& lat = prop.lattice;
    const Eigen::Vector3d z(rng.normal(), rng.normal(), rng.normal());
    p.pose = perturbed(prop.mode, lat.mean + prop.cov_factor * z);
    estimate = perturbed(prop.mode, lat.mean);
    p.log_weight += lat.log_eta;
    p.path_log_weight += lat.log_eta;
  } else {
    // Odometry proposal. The weight is the same lattice estimate of the
    // normaliser, taken around the sampled pose, so that particles on either
    // proposal stay comparable.
    //
    // On a scan with too few beams for the weights to tell particles apart
    // (nothing in range, or a few returns: open ground outdoors) the
    // particle moves by the odometry alone. The motion model's noise is wide
    // on purpose, so that the match's proposal reaches the true pose: the
    // odometry's real error is 0.06-0.76 of the model's sigma in heading
    // and 0.15-0.51 in position on the shared logs (RMS over each log's
    // steps against its reference). It is the scan, through the match or
    // the weights, that then picks the pose within that spread. With
    // neither there is nothing to pick, and a drawn turn of that size stays
    // in the particle's path: after 5 m of open ground the best particle was
    // up to 0.5 rad off where the odometry was 0.01 rad off (grid_rbpf_test,
    // "AStretchWithout..."). A scan with beams enough that fails to match
    // says the odometry is off: there the drawn spread is what the weights
    // choose from.
    const Pose2D from = p.pose;
    const bool dead_reckon = opt_.proposal == ProposalKind::kOptimal && !st.can_weigh;
    p.pose = dead_reckon ? from + u : motion_.sample(from, u, rng);
    if (!st.match->points().hit.empty()) {
      const Lattice lat =
          evaluate_lattice(p.map, from, u, st.lattice_pts, st.lattice_scale, p.pose,
                           st.sample_angular);
      if (lat.ok) {
        p.log_weight += lat.log_eta;
        p.path_log_weight += lat.log_eta;
      }
    }
  }
  p.path.push_back(p.pose);
  p.estimates.push_back(fallback ? p.pose : estimate);
  maybe_insert(p, st.step.scan);
  st.fell_back[i] = fallback;
}

// A step moved by the odometry alone (place(): too few beams to weigh):
// x' = x (+) (u + n), n ~ N(0, Q) in the frame of x, Q the motion model's
// (isotropic in x, y, so rotating it leaves it as it is), propagated along
// the best particle's path.
void GridRbpf::add_blind_step() {
  const size_t b = best_index();
  const Particle& p = particles_[b];
  if (!step_->fell_back[b] || p.path.size() < 2) return;
  const Pose2D& from = p.path[p.path.size() - 2];
  const Pose2D& u = step_->step.odometry_increment;
  const double c = std::cos(from.theta), s = std::sin(from.theta);
  Eigen::Matrix3d J = Eigen::Matrix3d::Identity();
  J(0, 2) = -s * u.x - c * u.y;
  J(1, 2) = c * u.x - s * u.y;
  const MotionSigmas q = motion_.sigmas(u);
  blind_cov_ = J * blind_cov_ * J.transpose();
  blind_cov_.diagonal() += Eigen::Vector3d(q.xy * q.xy, q.xy * q.xy, q.theta * q.theta);
}

void GridRbpf::record_blind() {
  // Only once a step has been blind does the trace hold matrices: until
  // then it stands for zeros, one per entry of the paths before this step's.
  if (blind_trace_.empty()) {
    if (blind_cov_.isZero(0.0)) return;
    blind_trace_.assign(particles_.front().path.size() - 1, Eigen::Matrix3d::Zero());
  }
  blind_trace_.push_back(blind_cov_);
}

void GridRbpf::reset_blind() {
  blind_cov_.setZero();
  blind_trace_.clear();
}

void GridRbpf::end_step() {
  if (!step_) return;
  if (!step_->can_weigh && opt_.proposal == ProposalKind::kOptimal) add_blind_step();
  record_blind();
  stats_.particle_moves += step_->fell_back.size();
  for (char f : step_->fell_back) stats_.odometry_fallbacks += (f != 0);
  std::vector<double> after(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i) after[i] = particles_[i].log_weight;
  // sum_i w_i exp(delta_i) with w the normalised weights before the step.
  last_log_evidence_ = log_sum_exp(after) - log_sum_exp(step_->before);
  step_.reset();
  resample_if_needed();
}

std::vector<double> GridRbpf::weights() const {
  std::vector<double> lw(particles_.size());
  for (size_t i = 0; i < particles_.size(); ++i) lw[i] = particles_[i].log_weight;
  return normalised_exp(std::move(lw));
}

double GridRbpf::ess() const {
  double s = 0.0;
  for (double w : weights()) s += w * w;
  return s > 0 ? 1.0 / s : 0.0;
}

size_t GridRbpf::best_index() const {
  size_t best = 0;
  for (size_t i = 1; i < particles_.size(); ++i)
    if (particles_[i].path_log_weight > particles_[best].path_log_weight) best = i;
  return best;
}

void GridRbpf::resample_if_needed() {
  const std::vector<double> w = weights();
  double s2 = 0.0;
  for (double x : w) s2 += x * x;
  const double n = static_cast<double>(w.size());
  // Keep the log weights near zero so they never lose precision on long runs
  // (a common shift changes neither the normalised weights nor the order).
  double top_w = particles_[0].log_weight, top_path = particles_[0].path_log_weight;
  for (const auto& p : particles_) {
    top_w = std::max(top_w, p.log_weight);
    top_path = std::max(top_path, p.path_log_weight);
  }
  for (auto& p : particles_) {
    p.log_weight -= top_w;
    p.path_log_weight -= top_path;
  }
  if (1.0 / s2 >= opt_.resample_threshold * n) return;
  draw(w, particles_.size());
  ++stats_.resamplings;
}

void GridRbpf::draw(const std::vector<double>& w, size_t count) {
  // Systematic (low-variance) resampling.
  std::vector<Particle> next;
  next.reserve(count);
  const double step = 1.0 / static_cast<double>(count);
  double u = rng_.uniform() * step, c = w[0];
  size_t i = 0;
  for (size_t k = 0; k < count; ++k) {
    while (u > c && i + 1 < w.size()) c += w[++i];
    next.push_back(particles_[i]);  // maps share tiles; paths are copied
    next.back().log_weight = 0.0;
    u += step;
  }
  particles_ = std::move(next);
}

void GridRbpf::resize(size_t n) {
  if (n == 0) throw Error(ExitCode::kInternal, "GridRbpf::resize(0)");
  if (particles_.empty() || n == particles_.size()) return;
  draw(weights(), n);
}

std::vector<Pose2D> GridRbpf::start_new_area(const std::vector<SeedScan>& seeds,
                                             size_t seed_particle) {
  if (particles_.empty())
    throw Error(ExitCode::kInternal, "start_new_area() before the first scan");
  if (seed_particle >= particles_.size())
    throw Error(ExitCode::kInternal, "start_new_area(): no such particle");
  const Particle& sp = particles_[seed_particle];
  for (const SeedScan& s : seeds)
    if (!s.scan || s.path_index >= sp.path.size())
      throw Error(ExitCode::kInternal, "start_new_area(): seed scan outside the area's path");
  // The pending odometry is motion after the last filtered pose, which
  // becomes the new origin: it is kept, expressed from that origin as before.
  grid::OccupancyGrid fresh(opt_.resolution);
  for (const SeedScan& s : seeds)
    grid::insert_scan(fresh, sp.path[s.path_index] - sp.pose, *s.scan, opt_.insertion);
  grid::insert_scan(fresh, Pose2D(), last_scan_, opt_.insertion);
  std::vector<Pose2D> origins;
  origins.reserve(particles_.size());
  for (auto& p : particles_) {
    origins.push_back(p.pose);
    p.map = fresh;
    // The estimate goes on from where it was, seen from the new origin.
    p.estimates.assign(1, p.estimates.back() - p.pose);
    p.pose = Pose2D();
    p.path.assign(1, p.pose + pending_motion_);
    p.last_insertion = p.pose;
    p.inserted = true;
  }
  // The new area's frame is the robot's pose now: the error so far is the
  // arc's (the caller has read blind_cov()).
  reset_blind();
  return origins;
}

bool GridRbpf::tracks_in(const grid::OccupancyGrid& map, const Pose2D& pose) const {
  const ScanPoints pts = prepare_scan(last_scan_, opt_.matcher.max_range,
                                      opt_.matcher.beam_skip, opt_.resolution);
  return pts.hit.empty() || opt_.matcher.tracks(matcher_.score(map, pose, pts).matched,
                                                pts.hit.size());
}

void GridRbpf::load_area(const grid::OccupancyGrid& map, const std::vector<Pose2D>& poses,
                         const Pose2D* view_at) {
  if (particles_.empty())
    throw Error(ExitCode::kInternal, "load_area() before the first scan");
  // The poses come from a match in the known area: it located the robot.
  reset_blind();
  if (poses.size() != 1 && poses.size() != particles_.size())
    throw Error(ExitCode::kInternal, "load_area(): need one pose or one per particle");
  // Without the last scan, particles that find nothing to match all fall
  // back on the odometry and spread by the motion model's wide noise: after
  // a closure at an area's edge they ended 0.2 rad off within a few steps.
  // The scan fills only what the map never observed: where it has, its own
  // evidence stands, and matching the next scans against it can still
  // correct the closure's pose (filling wherever the map could track the
  // robot, or overwriting it, did worse on the shared logs).
  grid::OccupancyGrid entered = map;  // shares the tiles; only filled ones are copied
  if (view_at && !tracks_in(map, *view_at)) {
    grid::OccupancyGrid view(map.resolution());
    grid::insert_scan(view, *view_at, last_scan_, opt_.insertion);
    grid::CellIndex lo, hi;
    if (view.bounds(&lo, &hi))
      for (int y = lo.y; y <= hi.y; ++y)
        for (int x = lo.x; x <= hi.x; ++x) {
          const grid::CellIndex c{x, y};
          const grid::Cell v = view.cell(c);
          if (v.logodds != 0 && map.logodds(c) == 0) entered.set_cell(c, v);
        }
  }
  // The given poses are the robot's poses now, after any pending odometry.
  pending_motion_ = Pose2D();
  for (size_t i = 0; i < particles_.size(); ++i) {
    Particle& p = particles_[i];
    p.map = entered;
    p.pose = poses.size() == 1 ? poses[0] : poses[i];
    p.path.assign(1, p.pose);
    p.estimates.assign(1, p.pose);
    p.last_insertion = p.pose;
    p.inserted = true;
  }
}

void GridRbpf::restart(const grid::OccupancyGrid& map, const Pose2D& pose) {
  reset_blind();
  Particle p;
  p.map = map;
  p.pose = pose;
  p.path.assign(1, pose);
  p.estimates.assign(1, pose);
  p.last_insertion = pose;
  p.inserted = true;
  particles_.assign(static_cast<size_t>(opt_.particles), p);
  pending_motion_ = Pose2D();
}

size_t GridRbpf::map_memory_bytes() const {
  grid::TileTally tally;
  for (const auto& p : particles_) tally.add(p.map);
  return tally.bytes();
}

}  // namespace hmt::metric_slam
