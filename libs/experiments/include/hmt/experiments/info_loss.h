// The information-loss ratio of a partition of the observations (000 Sec.
// 6.1, Eq. 22) and the partitions compared in Fig. 8.
//
//            sum_{(i,j): C(i) n C(j) = {}} |H(i,j)|
//       e = ----------------------------------------
//                    sum_{a,b} |H(a,b)|
//
// H is the information matrix of the EKF map, H(i,j) its block for landmarks
// i and j, C(i) the set of clusters landmark i belongs to: the groups of
// observations that contain an observation sensing it (a landmark seen from
// two groups is in both, and its links to either group's landmarks are kept).
//
// Where the paper leaves a choice, this follows the authors' own
// implementation (MRPT's CRangeBearingKFSLAM::
// computeOffDiagonalBlocksApproximationError):
//  - H is the inverse of the filter's joint covariance of robot pose and map
//    (the "information matrix" of the EKF), and only its landmark rows and
//    columns enter e. InformationForm::kMarginal instead inverts the map's
//    marginal covariance (the robot pose integrated out); both are offered.
//  - |H(i,j)| is the sum of the absolute values of the four entries of the
//    2x2 block; the denominator runs over all landmark blocks, the diagonal
//    ones included (those are never lost: a landmark shares its clusters with
//    itself).
//  - The fixed-size alternative uses disjoint groups of k consecutive
//    observations (MRPT's version shares one observation between consecutive
//    groups; the paper does not say so).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/landmark_sso.h"
#include "hmt/area/ncut.h"
#include "hmt/area/pose_gaussian.h"
#include "hmt/experiments/ekf_slam.h"
#include "hmt/experiments/landmark_sim.h"

namespace hmt::experiments {

enum class InformationForm { kJoint, kMarginal };
const char* to_string(InformationForm f);
// "joint" / "marginal"; throws std::invalid_argument otherwise.
InformationForm parse_information_form(const std::string& s);

// Information matrix of the landmarks (2L x 2L, state order) from the joint
// covariance of [robot (vehicle_size), landmarks (2 each)].
Eigen::MatrixXd landmark_information(const Eigen::MatrixXd& joint_cov,
                                     int vehicle_size, InformationForm form);

// C(i) for every landmark of the map: membership[k] = sorted groups with an
// observation that sensed map_ids[k]. obs_ids[t] = landmark ids sensed by
// observation t; groups partition (some of) 0..obs_ids.size()-1.
std::vector<std::vector<int>> landmark_membership(
    const std::vector<std::vector<int>>& obs_ids,
    const std::vector<std::vector<int>>& groups, const std::vector<int>& map_ids);

// Eq. 22 for an information matrix over 2 * membership.size() landmark
// coordinates. Throws std::invalid_argument on a size mismatch.
double information_loss(const Eigen::MatrixXd& H,
                        const std::vector<std::vector<int>>& membership);

// Sub-maps of a partition: its groups holding at least one observation that
// sensed a landmark (an observation that senses nothing shares nothing with
// the others and is split off as a group of its own at any tau > 0; such a
// group holds no map and is not counted).
int submap_count(const std::vector<std::vector<int>>& obs_ids,
                 const std::vector<std::vector<int>>& groups);

// m consecutive groups of n / m observations (sizes differ by at most one).
std::vector<std::vector<int>> even_groups(int n, int m);

// Consecutive groups of k observations (the last one may be shorter): the
// "new sub-map every k observations" alternative of Fig. 8(b).
std::vector<std::vector<int>> fixed_size_groups(int n, int k);

// Landmark observations as the area library sees them: each measurement a
// Gaussian in the robot frame; with `with_ids` its landmark id is attached as
// a one-element descriptor (then SsoOptions::descriptor_threshold = 0.5 makes
// only the same landmark match, as when features carry descriptors, 000 Sec.
// 3.1).
struct ObservationNode {
  area::PoseGaussian pose;
  area::LandmarkObservation obs;
  std::vector<int> ids;  // sorted
};
std::vector<ObservationNode> observation_nodes(const LandmarkSim& sim,
                                               const std::vector<PoseEstimate>& poses,
                                               const LandmarkSimOptions& options,
                                               bool with_ids);

// The SSO weight matrix of the observations (landmark SSO of hmt_area, 000
// Eq. 13-15), zero diagonal, entries below min_sso dropped. Pairs that cannot
// share a landmark (no common id when `ids_known`, otherwise poses further
// apart than 2 * reach + a 4-sigma margin) are not evaluated.
area::WeightMatrix landmark_sso_matrix(const std::vector<ObservationNode>& nodes,
                                       const area::SsoOptions& sso, double min_sso,
                                       bool ids_known, double reach);

struct InfoLossOptions {
  LandmarkSimOptions sim;
  // Fig. 8(b): the spectral partition with tau against fixed k in [k_min, k_max].
  double tau = 0.2;
  int k_min = 2;
  int k_max = 45;
  // Fig. 8(c): e against tau. The first value stands for the paper's tau = 0
  // ("sub-maps created only when no observation senses two landmarks from
  // different clusters"): the area library accepts a bisection when
  // Ncut < tau, so tau = 0 itself never splits, while a tiny tau splits
  // exactly the zero-Ncut (disconnected) parts.
  std::vector<double> taus = {1e-6, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5,
                              0.55, 0.6,  0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 1.0};
  InformationForm form = InformationForm::kJoint;
  // SSO: the landmark ids are used as descriptors (see observation_nodes).
  bool use_ids = true;
  area::SsoOptions sso;  // gate, descriptor threshold
  double min_sso = 1e-3;
  area::SplitMethod split_method = area::SplitMethod::kMean;
  int runs = 150;
  uint64_t seed = 1;
  int threads = 2;

  void validate() const;
};

struct RunResult {
  int run = 0;
  int observations = 0;
  int landmarks_mapped = 0;
  double e_spectral = 0.0;  // at options.tau
  int groups_spectral = 0;      // sub-maps (submap_count)
  // Control: as many consecutive groups of (nearly) equal size as the
  // spectral partition has sub-maps, i.e. the same number of cuts, evenly
  // spaced instead of placed by the min-Ncut.
  double e_even = 0.0;
  std::vector<double> e_fixed;  // k = k_min .. k_max
  std::vector<int> groups_fixed;
  std::vector<double> e_tau;  // options.taus
  std::vector<int> groups_tau;
};

// What Fig. 8(a) shows for one run.
struct RunDetail {
  LandmarkSim sim;
  std::vector<PoseEstimate> poses;    // after each step's update
  std::vector<int> map_ids;           // state order
  std::vector<Eigen::Vector2d> map_means;
  std::vector<Eigen::Matrix2d> map_covs;
  std::vector<int> spectral_labels;   // group of each observation (tau)
};

// One run with the seed of run `run` (independent of threads and order).
RunResult run_info_loss_once(const InfoLossOptions& options, int run,
                             RunDetail* detail = nullptr);

// All runs on options.threads threads, in run order. `progress(done)` is
// called (from one thread at a time) after each run.
std::vector<RunResult> run_info_loss(const InfoLossOptions& options,
                                     const std::function<void(int)>& progress = {});

struct Stats {
  int n = 0;
  double mean = 0.0, std = 0.0;  // std: sample standard deviation (n - 1)
  double p16 = 0.0, median = 0.0, p84 = 0.0;  // the central 68% and the median
  double min = 0.0, max = 0.0;
};
// Percentiles by linear interpolation between order statistics.
Stats summarize(std::vector<double> values);

}  // namespace hmt::experiments
