#include "hmt/experiments/info_loss.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <numeric>
#include <set>

#include "hmt/area/partition.h"

namespace hmt::experiments {
namespace {

TEST(experiments_InfoLoss, FixedSizeGroupsPartitionInOrder) {
  const auto g = fixed_size_groups(7, 3);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0], (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(g[1], (std::vector<int>{3, 4, 5}));
  EXPECT_EQ(g[2], (std::vector<int>{6}));
  EXPECT_EQ(fixed_size_groups(4, 10).size(), 1u);
  EXPECT_THROW(fixed_size_groups(4, 0), std::invalid_argument);
}

TEST(experiments_InfoLoss, MembershipIsEveryGroupThatSensedTheLandmark) {
  // Observations 0..3 sensing landmark ids; groups {0,1} and {2,3}.
  const std::vector<std::vector<int>> obs = {{10, 11}, {11}, {11, 12}, {12}};
  const auto m = landmark_membership(obs, {{0, 1}, {2, 3}}, {12, 10, 11, 99});
  EXPECT_EQ(m[0], (std::vector<int>{1}));
  EXPECT_EQ(m[1], (std::vector<int>{0}));
  EXPECT_EQ(m[2], (std::vector<int>{0, 1}));
  EXPECT_TRUE(m[3].empty());  // never sensed
}

TEST(experiments_InfoLoss, EvenGroups) {
  const auto g = even_groups(10, 3);
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0], (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(g[1], (std::vector<int>{3, 4, 5}));
  EXPECT_EQ(g[2], (std::vector<int>{6, 7, 8, 9}));
  EXPECT_EQ(even_groups(5, 5).size(), 5u);
  EXPECT_THROW(even_groups(5, 6), std::invalid_argument);
  EXPECT_THROW(even_groups(5, 0), std::invalid_argument);
}

TEST(experiments_InfoLoss, SubmapsAreGroupsThatSensedSomething) {
  const std::vector<std::vector<int>> obs = {{1}, {}, {}, {1, 2}, {}};
  EXPECT_EQ(submap_count(obs, {{0}, {1, 2}, {3, 4}}), 2);
  EXPECT_EQ(submap_count(obs, {{0, 1, 2, 3, 4}}), 1);
  EXPECT_EQ(submap_count(obs, {{1}, {2}, {4}}), 0);
}

TEST(experiments_InfoLoss, Eq22OnAHandMadeMatrix) {
  // Three landmarks; blocks of H filled with known values (signs included,
  // Eq. 22 takes absolute values).
  Eigen::MatrixXd H(6, 6);
  auto block = [&](int i, int j, double v) {
    H.block<2, 2>(2 * i, 2 * j).setConstant(v);
    H.block<2, 2>(2 * j, 2 * i).setConstant(v);
  };
  block(0, 0, 10);
  block(1, 1, 10);
  block(2, 2, 10);
  block(0, 1, -2);
  block(0, 2, 1);
  block(1, 2, 3);
  const double total = 4 * (3 * 10 + 2 * (2 + 1 + 3));
  // Landmarks 0 and 1 share group 0; 2 is alone in group 1.
  const double e = information_loss(H, {{0}, {0}, {1}});
  EXPECT_NEAR(e, 4 * 2 * (1 + 3) / total, 1e-15);
  // One group: nothing lost. Everyone alone: every off-diagonal block lost.
  EXPECT_EQ(information_loss(H, {{0}, {0}, {0}}), 0.0);
  EXPECT_NEAR(information_loss(H, {{0}, {1}, {2}}), 4 * 2 * (2 + 1 + 3) / total, 1e-15);
  // A landmark in both groups keeps its links to both.
  EXPECT_NEAR(information_loss(H, {{0}, {0, 1}, {1}}), 4 * 2 * 1 / total, 1e-15);
  EXPECT_THROW(information_loss(H, {{0}, {0}}), std::invalid_argument);
}

TEST(experiments_InfoLoss, JointAndMarginalInformation) {
  // A random SPD joint covariance of a robot and two landmarks.
  Random rng(5);
  Eigen::MatrixXd A(7, 7);
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) A(i, j) = rng.normal();
  const Eigen::MatrixXd P = A * A.transpose() + 0.5 * Eigen::MatrixXd::Identity(7, 7);
  const Eigen::MatrixXd Hj = landmark_information(P, 3, InformationForm::kJoint);
  const Eigen::MatrixXd Hm = landmark_information(P, 3, InformationForm::kMarginal);
  EXPECT_TRUE(Hj.isApprox(P.inverse().bottomRightCorner(4, 4), 1e-10));
  EXPECT_TRUE(Hm.isApprox(P.bottomRightCorner(4, 4).inverse(), 1e-10));
  // Conditioning on the robot adds information: Hj - Hm is PSD (Schur).
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hj - Hm).eigenvalues();
  EXPECT_GT(ev.minCoeff(), -1e-9);
  EXPECT_EQ(parse_information_form("joint"), InformationForm::kJoint);
  EXPECT_THROW(parse_information_form("full"), std::invalid_argument);
}

TEST(experiments_InfoLoss, SummaryStatistics) {
  const Stats s = summarize({4, 1, 3, 2, 5});
  EXPECT_EQ(s.n, 5);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_NEAR(s.std, std::sqrt(2.5), 1e-12);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_NEAR(s.p16, 1.64, 1e-12);
  EXPECT_NEAR(s.p84, 4.36, 1e-12);
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 5.0);
}

// A real run, built step by step: the SSO graph of the observations and the
// loss of several partitions of them.
class experiments_InfoLossRun : public ::testing::Test {
 protected:
  void SetUp() override {
    Random rng(11);
    sim_ = simulate_straight_path(o_, rng);
    ekf_ = std::make_unique<EkfSlam2D>(run_ekf(sim_, o_, &poses_));
    H_ = landmark_information(ekf_->covariance(), 3, InformationForm::kJoint);
    for (const SimStep& s : sim_.steps) {
      obs_ids_.emplace_back();
      for (const RangeBearing& m : s.z) obs_ids_.back().push_back(m.id);
    }
  }
  double loss(const std::vector<std::vector<int>>& groups) const {
    return information_loss(H_, landmark_membership(obs_ids_, groups, ekf_->landmark_ids()));
  }
  int n() const { return static_cast<int>(sim_.steps.size()); }

  LandmarkSimOptions o_;
  LandmarkSim sim_;
  std::vector<PoseEstimate> poses_;
  std::unique_ptr<EkfSlam2D> ekf_;
  Eigen::MatrixXd H_;
  std::vector<std::vector<int>> obs_ids_;
};

TEST_F(experiments_InfoLossRun, OneGroupLosesNothingAndLossIsARatio) {
  EXPECT_EQ(n(), 251);
  EXPECT_GT(ekf_->landmark_count(), 40);
  EXPECT_EQ(loss(fixed_size_groups(n(), n())), 0.0);
  for (int k : {1, 2, 5, 20, 45}) {
    const double e = loss(fixed_size_groups(n(), k));
    EXPECT_GT(e, 0.0) << k;
    EXPECT_LT(e, 1.0) << k;
  }
}

TEST_F(experiments_InfoLossRun, RefiningAPartitionNeverLosesLess) {
  // Groups of k refine groups of 2k (and of 4k): every pair kept by the finer
  // partition is kept by the coarser one.
  for (int k : {2, 3, 5, 8, 11}) {
    const double fine = loss(fixed_size_groups(n(), k));
    const double coarse = loss(fixed_size_groups(n(), 2 * k));
    const double coarser = loss(fixed_size_groups(n(), 4 * k));
    EXPECT_GE(fine, coarse) << k;
    EXPECT_GE(coarse, coarser) << k;
  }
  EXPECT_GT(loss(fixed_size_groups(n(), 2)), loss(fixed_size_groups(n(), 45)));
}

TEST_F(experiments_InfoLossRun, SsoGraphOfTheObservations) {
  const auto nodes = observation_nodes(sim_, poses_, o_, true);
  ASSERT_EQ(static_cast<int>(nodes.size()), n());
  area::SsoOptions sso;
  sso.descriptor_threshold = 0.5;
  const area::WeightMatrix W = landmark_sso_matrix(nodes, sso, 1e-3, true, o_.max_range);
  EXPECT_NO_THROW(area::check_weight_matrix(W));
  const Eigen::MatrixXd D = W;
  EXPECT_TRUE(D.diagonal().isZero(0.0));
  // Consecutive observations (0.2 m apart) see nearly the same landmarks.
  int strong = 0, pairs = 0;
  for (int t = 0; t + 1 < n(); ++t) {
    if (nodes[t].ids.empty() || nodes[t + 1].ids.empty()) continue;
    ++pairs;
    if (D(t, t + 1) > 0.6) ++strong;
  }
  EXPECT_GT(strong, 0.9 * pairs);
  // Observations 12 m apart cannot share a landmark (6 m range, forward FOV).
  for (int t = 0; t + 60 < n(); ++t) EXPECT_EQ(D(t, t + 60), 0.0);
  // Without ids the Mahalanobis test alone decides; with these small noises it
  // finds the same overlaps almost everywhere.
  const area::WeightMatrix W2 =
      landmark_sso_matrix(observation_nodes(sim_, poses_, o_, false), area::SsoOptions(),
                          1e-3, false, o_.max_range);
  const Eigen::MatrixXd D2 = W2;
  EXPECT_LT((D2 - D).cwiseAbs().sum(), 0.05 * D.sum());
}

TEST(experiments_InfoLoss, RunsAreReproducibleAndIndependentOfThreads) {
  InfoLossOptions o;
  o.runs = 3;
  o.taus = {0.0, 0.2, 0.6, 1.0};
  o.k_max = 10;
  o.threads = 1;
  const auto one = run_info_loss(o);
  o.threads = 2;
  const auto two = run_info_loss(o);
  ASSERT_EQ(one.size(), 3u);
  for (size_t r = 0; r < one.size(); ++r) {
    EXPECT_EQ(one[r].e_fixed, two[r].e_fixed);
    EXPECT_EQ(one[r].e_tau, two[r].e_tau);
    EXPECT_EQ(one[r].e_spectral, two[r].e_spectral);
    EXPECT_EQ(one[r].groups_spectral, two[r].groups_spectral);
  }
  EXPECT_NE(one[0].e_fixed, one[1].e_fixed);  // different runs, different worlds
  const RunResult again = run_info_loss_once(o, 1);
  EXPECT_EQ(again.e_tau, one[1].e_tau);
}

TEST(experiments_InfoLoss, LowerTauNeverLosesMore) {
  // With a lower threshold the recursive partition accepts a subset of the
  // same bisections, so its groups are unions of the higher tau's groups.
  InfoLossOptions o;
  o.taus = {0.0, 0.1, 0.2, 0.4, 0.7, 1.0, 1.5};
  o.k_max = 2;
  for (int run = 0; run < 3; ++run) {
    const RunResult r = run_info_loss_once(o, run);
    EXPECT_EQ(r.e_tau.front(), 0.0);  // tau = 0 never splits
    EXPECT_EQ(r.groups_tau.front(), 1);
    for (size_t i = 1; i < r.e_tau.size(); ++i) {
      EXPECT_GE(r.e_tau[i], r.e_tau[i - 1]) << run << " " << o.taus[i];
      EXPECT_GE(r.groups_tau[i], r.groups_tau[i - 1]);
    }
    EXPECT_EQ(r.e_spectral, r.e_tau[2]);  // tau = 0.2
    EXPECT_GT(r.groups_tau.back(), 1);
  }
}

TEST(experiments_InfoLoss, DetailDescribesTheRun) {
  InfoLossOptions o;
  o.k_max = 2;
  o.taus = {0.2};
  RunDetail d;
  const RunResult r = run_info_loss_once(o, 0, &d);
  EXPECT_EQ(d.poses.size(), d.sim.steps.size());
  EXPECT_EQ(d.spectral_labels.size(), d.sim.steps.size());
  EXPECT_EQ(static_cast<int>(d.map_ids.size()), r.landmarks_mapped);
  // Groups of labels holding an observation that sensed something.
  std::set<int> with_landmarks;
  for (size_t t = 0; t < d.sim.steps.size(); ++t)
    if (!d.sim.steps[t].z.empty()) with_landmarks.insert(d.spectral_labels[t]);
  EXPECT_EQ(static_cast<int>(with_landmarks.size()), r.groups_spectral);
  EXPECT_GT(r.groups_spectral, 1);
  // The estimated map is close to the truth.
  for (size_t k = 0; k < d.map_ids.size(); ++k) {
    const Point2D t = d.sim.landmarks[d.map_ids[k]];
    EXPECT_LT((d.map_means[k] - Eigen::Vector2d(t.x, t.y)).norm(), 1.5);
  }
}

TEST(experiments_InfoLoss, OptionsAreValidated) {
  InfoLossOptions o;
  o.runs = 0;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = InfoLossOptions();
  o.taus = {0.2, 3.0};
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o = InfoLossOptions();
  o.sim.step = -1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::experiments
