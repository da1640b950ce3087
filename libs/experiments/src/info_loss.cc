#include "hmt/experiments/info_loss.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "hmt/area/landmark_sso.h"
#include "hmt/area/partition.h"

namespace hmt::experiments {
namespace {

// The inverse of a symmetric positive definite matrix (LDLT when the
// Cholesky factorisation fails on rounding).
Eigen::MatrixXd spd_inverse(const Eigen::MatrixXd& A) {
  const Eigen::Index n = A.rows();
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() == Eigen::Success) return llt.solve(I);
  Eigen::LDLT<Eigen::MatrixXd> ldlt(A);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive())
    throw std::runtime_error("information matrix: covariance is not positive definite");
  return ldlt.solve(I);
}

uint64_t run_seed(uint64_t seed, int run) {
  // splitmix64 of (seed, run): neighbouring runs get unrelated streams.
  uint64_t z = seed * 0x9E3779B97F4A7C15ULL + static_cast<uint64_t>(run) + 1;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

bool share_element(const std::vector<int>& a, const std::vector<int>& b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (a[i] == b[j]) return true;
    if (a[i] < b[j])
      ++i;
    else
      ++j;
  }
  return false;
}

}  // namespace

const char* to_string(InformationForm f) {
  return f == InformationForm::kJoint ? "joint" : "marginal";
}

InformationForm parse_information_form(const std::string& s) {
  if (s == "joint") return InformationForm::kJoint;
  if (s == "marginal") return InformationForm::kMarginal;
  throw std::invalid_argument("information form '" + s +
                              "': must be 'joint' or 'marginal'");
}

Eigen::MatrixXd landmark_information(const Eigen::MatrixXd& joint_cov,
                                     int vehicle_size, InformationForm form) {
  const Eigen::Index n = joint_cov.rows();
  if (joint_cov.cols() != n || n < vehicle_size || (n - vehicle_size) % 2 != 0)
    throw std::invalid_argument("landmark_information: bad covariance size");
  const Eigen::Index m = n - vehicle_size;
  if (form == InformationForm::kMarginal)
    return spd_inverse(joint_cov.bottomRightCorner(m, m));
  return spd_inverse(joint_cov).bottomRightCorner(m, m);
}

std::vector<std::vector<int>> landmark_membership(
    const std::vector<std::vector<int>>& obs_ids,
    const std::vector<std::vector<int>>& groups, const std::vector<int>& map_ids) {
  std::map<int, int> slot;  // landmark id -> position in map_ids
  for (size_t k = 0; k < map_ids.size(); ++k) slot[map_ids[k]] = static_cast<int>(k);
  std::vector<std::vector<int>> membership(map_ids.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    for (int t : groups[g]) {
      if (t < 0 || t >= static_cast<int>(obs_ids.size()))
        throw std::invalid_argument("landmark_membership: observation out of range");
      for (int id : obs_ids[t]) {
        const auto it = slot.find(id);
        if (it == slot.end()) continue;
        auto& m = membership[it->second];
        if (m.empty() || m.back() != static_cast<int>(g)) m.push_back(static_cast<int>(g));
      }
    }
  }
  for (auto& m : membership) {
    std::sort(m.begin(), m.end());
    m.erase(std::unique(m.begin(), m.end()), m.end());
  }
  return membership;
}

double information_loss(const Eigen::MatrixXd& H,
                        const std::vector<std::vector<int>>& membership) {
  const Eigen::Index L = static_cast<Eigen::Index>(membership.size());
  if (H.rows() != 2 * L || H.cols() != 2 * L)
    throw std::invalid_argument("information_loss: H is not 2L x 2L");
  if (L == 0) return 0.0;
  const Eigen::MatrixXd A = H.cwiseAbs();
  const double total = A.sum();
  if (!(total > 0.0)) return 0.0;
  double lost = 0.0;
  for (Eigen::Index i = 0; i < L; ++i)
    for (Eigen::Index j = i + 1; j < L; ++j)
      if (!share_element(membership[i], membership[j]))
        lost += A.block<2, 2>(2 * i, 2 * j).sum() + A.block<2, 2>(2 * j, 2 * i).sum();
  return lost / total;
}

int submap_count(const std::vector<std::vector<int>>& obs_ids,
                 const std::vector<std::vector<int>>& groups) {
  int count = 0;
  for (const auto& g : groups)
    for (int t : g)
      if (!obs_ids.at(t).empty()) {
        ++count;
        break;
      }
  return count;
}

std::vector<std::vector<int>> even_groups(int n, int m) {
  if (m < 1 || m > std::max(n, 1))
    throw std::invalid_argument("even_groups: need 1 <= m <= n");
  std::vector<std::vector<int>> groups(m);
  for (int g = 0; g < m; ++g) {
    const int lo = static_cast<int>(static_cast<long>(g) * n / m);
    const int hi = static_cast<int>(static_cast<long>(g + 1) * n / m);
    for (int t = lo; t < hi; ++t) groups[g].push_back(t);
  }
  return groups;
}

std::vector<std::vector<int>> fixed_size_groups(int n, int k) {
  if (k < 1) throw std::invalid_argument("fixed_size_groups: k must be >= 1");
  std::vector<std::vector<int>> groups;
  for (int t = 0; t < n; ++t) {
    if (t % k == 0) groups.emplace_back();
    groups.back().push_back(t);
  }
  return groups;
}

std::vector<ObservationNode> observation_nodes(const LandmarkSim& sim,
                                               const std::vector<PoseEstimate>& poses,
                                               const LandmarkSimOptions& o,
                                               bool with_ids) {
  if (poses.size() != sim.steps.size())
    throw std::invalid_argument("observation_nodes: one pose per step needed");
  std::vector<ObservationNode> nodes(sim.steps.size());
  for (size_t t = 0; t < sim.steps.size(); ++t) {
    ObservationNode& node = nodes[t];
    node.pose = area::PoseGaussian(poses[t].mean, poses[t].cov);
    for (const RangeBearing& m : sim.steps[t].z) {
      area::Landmark l = area::landmark_from_range_bearing(
          Pose2D(), m.range, m.bearing, o.range_std, o.bearing_std);
      if (with_ids) l.descriptor = {static_cast<float>(m.id)};
      node.obs.landmarks.push_back(std::move(l));
      node.ids.push_back(m.id);
    }
    std::sort(node.ids.begin(), node.ids.end());
  }
  return nodes;
}

area::WeightMatrix landmark_sso_matrix(const std::vector<ObservationNode>& nodes,
                                       const area::SsoOptions& sso, double min_sso,
                                       bool ids_known, double reach) {
  const int n = static_cast<int>(nodes.size());
  std::vector<Eigen::Triplet<double>> trip;
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const ObservationNode& A = nodes[a];
      const ObservationNode& B = nodes[b];
      if (A.obs.landmarks.empty() || B.obs.landmarks.empty()) continue;
      if (ids_known) {
        if (!share_element(A.ids, B.ids)) continue;
      } else {
        const double d = std::hypot(A.pose.mean.x - B.pose.mean.x,
                                    A.pose.mean.y - B.pose.mean.y);
        const double sigma = std::sqrt(A.pose.cov(0, 0) + A.pose.cov(1, 1) +
                                       B.pose.cov(0, 0) + B.pose.cov(1, 1));
        if (d > 2.0 * reach + 4.0 * sigma) continue;
      }
      const double w = area::landmark_sso(A.obs, A.pose, B.obs, B.pose, sso);
      if (w >= min_sso && w > 0.0) {
        trip.emplace_back(a, b, w);
        trip.emplace_back(b, a, w);
      }
    }
  }
  area::WeightMatrix W(n, n);
  W.setFromTriplets(trip.begin(), trip.end());
  return W;
}

void InfoLossOptions::validate() const {
  sim.validate();
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("information-loss experiment: " + what);
  };
  if (!(tau >= 0.0 && tau <= 2.0)) fail("tau must be in [0, 2]");
  for (double t : taus)
    if (!(t >= 0.0 && t <= 2.0)) fail("every tau must be in [0, 2]");
  if (k_min < 1 || k_max < k_min) fail("need 1 <= k_min <= k_max");
  if (runs < 1) fail("runs must be >= 1");
  if (threads < 1) fail("threads must be >= 1");
  if (!(min_sso >= 0.0 && min_sso < 1.0)) fail("min_sso must be in [0, 1)");
}

RunResult run_info_loss_once(const InfoLossOptions& o, int run, RunDetail* detail) {
  Random rng(run_seed(o.seed, run));
  LandmarkSim sim = simulate_straight_path(o.sim, rng);
  std::vector<PoseEstimate> poses;
  const EkfSlam2D ekf = run_ekf(sim, o.sim, &poses);
  const Eigen::MatrixXd H =
      landmark_information(ekf.covariance(), EkfSlam2D::kVehicleSize, o.form);

  const int n = static_cast<int>(sim.steps.size());
  std::vector<std::vector<int>> obs_ids(n);
  for (int t = 0; t < n; ++t)
    for (const RangeBearing& m : sim.steps[t].z) obs_ids[t].push_back(m.id);

  area::SsoOptions sso = o.sso;
  if (o.use_ids && !(sso.descriptor_threshold > 0.0)) sso.descriptor_threshold = 0.5;
  const auto nodes = observation_nodes(sim, poses, o.sim, o.use_ids);
  const area::WeightMatrix W =
      landmark_sso_matrix(nodes, sso, o.min_sso, o.use_ids, o.sim.max_range);

  RunResult r;
  r.run = run;
  r.observations = n;
  r.landmarks_mapped = ekf.landmark_count();
  auto loss_of = [&](const std::vector<std::vector<int>>& groups) {
    return information_loss(H, landmark_membership(obs_ids, groups, ekf.landmark_ids()));
  };

  std::map<double, std::pair<double, std::vector<std::vector<int>>>> by_tau;
  auto spectral = [&](double tau) -> const std::pair<double, std::vector<std::vector<int>>>& {
    auto it = by_tau.find(tau);
    if (it != by_tau.end()) return it->second;
    area::PartitionOptions popt;
    popt.tau = tau;
    popt.min_cluster_size = 1;
    popt.split_method = o.split_method;
    auto groups = area::recursive_partition(W, popt).groups;
    const double e = loss_of(groups);
    return by_tau.emplace(tau, std::make_pair(e, std::move(groups))).first->second;
  };

  const auto& main = spectral(o.tau);
  r.e_spectral = main.first;
  r.groups_spectral = submap_count(obs_ids, main.second);
  r.e_even = loss_of(even_groups(n, std::max(r.groups_spectral, 1)));
  for (double tau : o.taus) {
    const auto& s = spectral(tau);
    r.e_tau.push_back(s.first);
    r.groups_tau.push_back(submap_count(obs_ids, s.second));
  }
  for (int k = o.k_min; k <= o.k_max; ++k) {
    const auto groups = fixed_size_groups(n, k);
    r.e_fixed.push_back(loss_of(groups));
    r.groups_fixed.push_back(submap_count(obs_ids, groups));
  }

  if (detail) {
    detail->sim = std::move(sim);
    detail->poses = std::move(poses);
    detail->map_ids = ekf.landmark_ids();
    detail->map_means.clear();
    detail->map_covs.clear();
    for (int k = 0; k < ekf.landmark_count(); ++k) {
      detail->map_means.push_back(ekf.landmark(k));
      detail->map_covs.push_back(ekf.landmark_cov(k));
    }
    detail->spectral_labels = area::group_labels(spectral(o.tau).second, n);
  }
  return r;
}

std::vector<RunResult> run_info_loss(const InfoLossOptions& o,
                                     const std::function<void(int)>& progress) {
  o.validate();
  std::vector<RunResult> results(o.runs);
  std::atomic<int> next{0};
  std::mutex mu;
  int done = 0;
  std::exception_ptr error;
  auto worker = [&] {
    while (true) {
      const int run = next.fetch_add(1);
      if (run >= o.runs) return;
      try {
        results[run] = run_info_loss_once(o, run);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mu);
        if (!error) error = std::current_exception();
        next = o.runs;
        return;
      }
      std::lock_guard<std::mutex> lock(mu);
      ++done;
      if (progress) progress(done);
    }
  };
  const int nthreads = std::min(o.threads, o.runs);
  std::vector<std::thread> pool;
  for (int i = 1; i < nthreads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  return results;
}

Stats summarize(std::vector<double> v) {
  Stats s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0.0;
  for (double x : v) sum += x;
  s.mean = sum / s.n;
  double ss = 0.0;
  for (double x : v) ss += (x - s.mean) * (x - s.mean);
  s.std = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0.0;
  auto pct = [&](double p) {
    const double pos = p * (s.n - 1);
    const int lo = static_cast<int>(std::floor(pos));
    const int hi = std::min(lo + 1, s.n - 1);
    return v[lo] + (pos - lo) * (v[hi] - v[lo]);
  };
  s.p16 = pct(0.16);
  s.median = pct(0.5);
  s.p84 = pct(0.84);
  s.min = v.front();
  s.max = v.back();
  return s;
}

}  // namespace hmt::experiments
