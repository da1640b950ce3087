#include "hmt/global_map/global_poses.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "hmt/common/random.h"
#include "hmt/topology/shortest_paths.h"

namespace hmt::global_map {
namespace {

using topology::HmtMap;
using topology::PoseGaussian;

Eigen::Matrix3d diag(double sx, double sy, double st) {
  return Eigen::Vector3d(sx * sx, sy * sy, st * st).asDiagonal();
}

Eigen::Vector3d vec(const Pose2D& p) { return {p.x, p.y, p.theta}; }

// Squared pose error, the heading wrapped.
double squared_error(const Pose2D& estimate, const Pose2D& truth) {
  return topology::difference(estimate, truth).squaredNorm();
}

// Ground truth of a square loop of six areas walked anticlockwise, each
// frame heading along the walk (the headings cross +-pi at areas 3 and 4).
std::vector<Pose2D> square_loop_truth() {
  return {Pose2D(0, 0, 0),           Pose2D(5, 0, 0),
          Pose2D(10, 0, M_PI / 2),   Pose2D(10, 5, M_PI),
          Pose2D(5, 5, M_PI),        Pose2D(0, 5, -M_PI / 2)};
}

const Eigen::Matrix3d kChainCov = diag(0.15, 0.15, 0.04);
const Eigen::Matrix3d kClosureCov = diag(0.7, 0.7, 0.12);

// The loop as the robot would map it: arcs i -> i+1 from crossings (small
// covariance) and a loop-closure arc 0 -> 5 from a map alignment (larger
// covariance, so the Dijkstra tree is the chain and leaves the closure
// out). Every arc is the true relative pose plus a draw of its noise.
HmtMap noisy_loop(const std::vector<Pose2D>& truth, Random& rng) {
  HmtMap m;
  for (size_t i = 0; i < truth.size(); ++i) m.add_area(static_cast<AreaId>(i));
  auto add = [&](AreaId a, AreaId b, const Eigen::Matrix3d& cov) {
    const PoseGaussian exact(truth[b] - truth[a], cov);
    m.add_arc_measurement(a, b, PoseGaussian(topology::sample(exact, rng), cov));
  };
  for (AreaId i = 0; i + 1 < truth.size(); ++i) add(i, i + 1, kChainCov);
  add(0, static_cast<AreaId>(truth.size() - 1), kClosureCov);
  return m;
}

double sse(const GlobalPoses& g, const std::vector<Pose2D>& truth) {
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i)
    sum += squared_error(g.poses.at(static_cast<AreaId>(i)).mean, truth[i]);
  return sum;
}

void expect_root_identity(const GlobalPoses& g) {
  const PoseGaussian& r = g.poses.at(g.root);
  EXPECT_EQ(vec(r.mean), Eigen::Vector3d::Zero());
  EXPECT_EQ(r.cov, Eigen::Matrix3d::Zero());
}

TEST(OptimizePoses, LoopBeatsShortestPathOnEveryCriterion) {
  const std::vector<Pose2D> truth = square_loop_truth();
  double sse_tree = 0.0, sse_optimized = 0.0;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    Random rng(seed);
    const HmtMap m = noisy_loop(truth, rng);
    const GlobalPoses tree = shortest_path_poses(m, 0);
    ASSERT_EQ(topology::shortest_paths(m, 0).path_to(5),
              (std::vector<AreaId>{0, 1, 2, 3, 4, 5}))
        << "the closure arc must be off the tree for this test";
    PoseGraphReport report;
    const GlobalPoses opt = optimize_poses(m, 0, {}, &report);

    EXPECT_TRUE(report.converged) << "seed " << seed;
    EXPECT_LE(report.iterations, 10) << "seed " << seed;
    EXPECT_DOUBLE_EQ(report.initial_chi2, chi2(m, tree));
    EXPECT_DOUBLE_EQ(report.final_chi2, chi2(m, opt));
    EXPECT_LT(report.final_chi2, report.initial_chi2) << "seed " << seed;
    expect_root_identity(opt);
    // The tree fits the chain exactly and puts the whole loop misfit on the
    // closure; the optimum spreads it over the loop.
    const topology::Arc& closure = *m.find_arc(0, 5);
    EXPECT_LT(arc_residual(closure, opt).norm(),
              arc_residual(closure, tree).norm())
        << "seed " << seed;
    sse_tree += sse(tree, truth);
    sse_optimized += sse(opt, truth);
  }
  // Noise can favour the tree on a single draw; over twenty the estimate
  // that uses every arc must be clearly closer to the truth.
  EXPECT_LT(sse_optimized, 0.8 * sse_tree)
      << "tree " << sse_tree << " optimized " << sse_optimized;
}

TEST(OptimizePoses, OptimumIsStationary) {
  // Wrong Jacobians would still converge, but to a point where the true
  // gradient of chi2 is not zero. Central differences of chi2 check it.
  Random rng(7);
  const HmtMap m = noisy_loop(square_loop_truth(), rng);
  const GlobalPoses tree = shortest_path_poses(m, 0);
  const GlobalPoses opt = optimize_poses(m, 0);
  auto gradient_norm = [&](const GlobalPoses& at) {
    double sum = 0.0;
    const double h = 1e-6;
    for (AreaId id = 1; id < 6; ++id)
      for (int k = 0; k < 3; ++k) {
        GlobalPoses plus = at, minus = at;
        double* p = k == 0 ? &plus.poses.at(id).mean.x
                    : k == 1 ? &plus.poses.at(id).mean.y
                             : &plus.poses.at(id).mean.theta;
        double* q = k == 0 ? &minus.poses.at(id).mean.x
                    : k == 1 ? &minus.poses.at(id).mean.y
                             : &minus.poses.at(id).mean.theta;
        *p += h;
        *q -= h;
        const double d = (chi2(m, plus) - chi2(m, minus)) / (2 * h);
        sum += d * d;
      }
    return std::sqrt(sum);
  };
  const double g_tree = gradient_norm(tree);
  EXPECT_GT(g_tree, 1.0);
  EXPECT_LT(gradient_norm(opt), 1e-6 * g_tree);
}

TEST(OptimizePoses, TreeGivesTheShortestPathPoses) {
  // No loop: every arc can be fitted exactly, the tree already does, and the
  // linearised covariances are the composed ones of Eq. 15.
  HmtMap m;
  for (AreaId i = 0; i < 5; ++i) m.add_area(i);
  m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(3, 1, 0.4), diag(0.1, 0.2, 0.05)));
  m.add_arc_measurement(1, 2, PoseGaussian(Pose2D(2, -1, 2.9), diag(0.2, 0.1, 0.03)));
  m.add_arc_measurement(3, 1, PoseGaussian(Pose2D(-1, 4, -2.5), diag(0.1, 0.1, 0.08)));
  m.add_arc_measurement(3, 4, PoseGaussian(Pose2D(1, 1, 3.1), diag(0.3, 0.1, 0.02)));
  const GlobalPoses tree = shortest_path_poses(m, 2);
  PoseGraphReport report;
  const GlobalPoses opt = optimize_poses(m, 2, {}, &report);
  EXPECT_TRUE(report.converged);
  EXPECT_LT(report.final_chi2, 1e-20);
  ASSERT_EQ(opt.poses.size(), tree.poses.size());
  for (const auto& [id, p] : tree.poses) {
    const PoseGaussian& q = opt.poses.at(id);
    EXPECT_LT(topology::difference(q.mean, p.mean).cwiseAbs().maxCoeff(), 1e-9)
        << "area " << id;
    EXPECT_LT((q.cov - p.cov).cwiseAbs().maxCoeff(),
              1e-9 * std::max(1.0, p.cov.cwiseAbs().maxCoeff()))
        << "area " << id;
  }
}

TEST(OptimizePoses, CovariancesGrowAwayFromTheRoot) {
  Random rng(3);
  const HmtMap m = noisy_loop(square_loop_truth(), rng);
  const GlobalPoses opt = optimize_poses(m, 0);
  for (AreaId id = 1; id < 6; ++id)
    EXPECT_TRUE(topology::is_positive_definite(opt.poses.at(id).cov))
        << "area " << id;
  // Area 3 is three arcs away either way round; area 1 is next to the root.
  EXPECT_GT(opt.poses.at(3).cov.trace(), 2.0 * opt.poses.at(1).cov.trace());
  // The loop closure adds information: every marginal is tighter than the
  // tree's composition along the chain, most of all at the chain's end.
  const GlobalPoses tree = shortest_path_poses(m, 0);
  for (AreaId id = 1; id < 6; ++id)
    EXPECT_LT(opt.poses.at(id).cov.trace(), tree.poses.at(id).cov.trace())
        << "area " << id;
  EXPECT_LT(opt.poses.at(5).cov.trace(), 0.5 * tree.poses.at(5).cov.trace());
}

// The residual of every arc at `g`, with its Jacobian by central
// differences (independent of the library's analytic ones), assembled into
// the dense information matrix over areas 1..n-1 (the root 0 fixed).
Eigen::MatrixXd dense_information(const HmtMap& m, const GlobalPoses& g,
                                  int areas) {
  const int n = 3 * (areas - 1);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
  const double h = 1e-6;
  for (const auto& [ends, arc] : m.arcs()) {
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3, n);
    for (AreaId id : {ends.first, ends.second}) {
      if (id == 0) continue;
      for (int k = 0; k < 3; ++k) {
        GlobalPoses plus = g, minus = g;
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d(k) = h;
        auto shift = [](Pose2D& p, const Eigen::Vector3d& s) {
          p = Pose2D(p.x + s(0), p.y + s(1), p.theta + s(2));
        };
        shift(plus.poses.at(id).mean, d);
        shift(minus.poses.at(id).mean, -d);
        J.col(3 * (id - 1) + k) =
            (arc_residual(arc, plus) - arc_residual(arc, minus)) / (2 * h);
      }
    }
    H += J.transpose() * arc.pose.cov.inverse() * J;
  }
  return H;
}

TEST(OptimizePoses, MarginalsMatchADenseInverse) {
  // A four-area loop with a diagonal: small enough to invert densely.
  HmtMap m;
  for (AreaId i = 0; i < 4; ++i) m.add_area(i);
  m.add_arc_measurement(0, 1, PoseGaussian(Pose2D(4, 0.2, 1.5), diag(0.1, 0.2, 0.05)));
  m.add_arc_measurement(1, 2, PoseGaussian(Pose2D(3.9, -0.1, 1.6), diag(0.2, 0.1, 0.04)));
  m.add_arc_measurement(2, 3, PoseGaussian(Pose2D(4.1, 0.3, 1.55), diag(0.15, 0.1, 0.06)));
  m.add_arc_measurement(3, 0, PoseGaussian(Pose2D(3.8, 0.0, 1.62), diag(0.3, 0.3, 0.1)));
  m.add_arc_measurement(0, 2, PoseGaussian(Pose2D(4.1, 3.9, 3.1), diag(0.4, 0.4, 0.1)));
  const GlobalPoses opt = optimize_poses(m, 0);
  const Eigen::MatrixXd inverse = dense_information(m, opt, 4).inverse();
  for (AreaId id = 1; id < 4; ++id) {
    const Eigen::Matrix3d expected = inverse.block<3, 3>(3 * (id - 1), 3 * (id - 1));
    const Eigen::Matrix3d& got = opt.poses.at(id).cov;
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(),
              1e-6 * expected.cwiseAbs().maxCoeff())
        << "area " << id << "\n" << got << "\nexpected\n" << expected;
    EXPECT_EQ(got, got.transpose());
  }
}

TEST(OptimizePoses, UnreachableAreasAreReportedAndSkipped) {
  Random rng(5);
  HmtMap m = noisy_loop(square_loop_truth(), rng);
  m.add_area(7);
  m.add_area(8);
  m.add_area(9);
  m.add_arc_measurement(7, 8, PoseGaussian(Pose2D(1, 0, 0), diag(0.1, 0.1, 0.1)));
  for (const GlobalPoses& g : {shortest_path_poses(m, 0), optimize_poses(m, 0)}) {
    EXPECT_EQ(g.unreachable, (std::vector<AreaId>{7, 8, 9}));
    EXPECT_EQ(g.poses.size(), 6u);
    EXPECT_EQ(g.poses.count(7), 0u);
  }
  // From an island, the island is all there is.
  PoseGraphReport report;
  const GlobalPoses island = optimize_poses(m, 9, {}, &report);
  EXPECT_EQ(island.poses.size(), 1u);
  EXPECT_EQ(island.unreachable.size(), 8u);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.iterations, 0);
  expect_root_identity(island);
}

TEST(OptimizePoses, IterationLimitIsReported) {
  Random rng(11);
  const HmtMap m = noisy_loop(square_loop_truth(), rng);
  PoseGraphOptions options;
  options.max_iterations = 1;
  PoseGraphReport report;
  optimize_poses(m, 0, options, &report);
  EXPECT_EQ(report.iterations, 1);
  EXPECT_FALSE(report.converged);
  EXPECT_LT(report.final_chi2, report.initial_chi2);
}

TEST(OptimizePoses, DeterministicAcrossRuns) {
  Random rng(13);
  const HmtMap m = noisy_loop(square_loop_truth(), rng);
  const GlobalPoses a = optimize_poses(m, 2), b = optimize_poses(m, 2);
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (const auto& [id, p] : a.poses) {
    EXPECT_EQ(vec(p.mean), vec(b.poses.at(id).mean));
    EXPECT_EQ(p.cov, b.poses.at(id).cov);
  }
}

// A ring of twelve areas around a block (radius 8 m), each frame heading
// along the walk, as the robot maps it: area i created from area i - 1
// (the chain of creating arcs, decimetre covariances from crossings) and
// two fine-aligned loop closures at the seam, 11 -> 0 and 1 -> 11
// (centimetre covariances).
std::vector<Pose2D> ring_truth() {
  std::vector<Pose2D> t;
  for (int i = 0; i < 12; ++i) {
    const double a = 2 * M_PI * i / 12;
    t.emplace_back(8 * std::sin(a), 8 - 8 * std::cos(a), a);
  }
  return t;
}

const Eigen::Matrix3d kCrossingCov = diag(0.10, 0.10, 0.02);
const Eigen::Matrix3d kAlignedCov = diag(0.03, 0.03, 0.005);

// One area per pose of `truth`, each created from the one before (no arcs).
HmtMap ring_areas(const std::vector<Pose2D>& truth) {
  HmtMap m;
  for (AreaId i = 0; i < truth.size(); ++i) {
    topology::ReferenceFrame f;
    if (i > 0) f.parent = i - 1;
    m.add_area(i, f);
  }
  return m;
}

// `rng` null: every arc's mean is exact.
HmtMap ring_map(const std::vector<Pose2D>& truth, Random* rng) {
  HmtMap m = ring_areas(truth);
  auto add = [&](AreaId a, AreaId b, const Eigen::Matrix3d& cov) {
    const PoseGaussian exact(truth[b] - truth[a], cov);
    m.add_arc_measurement(
        a, b, rng ? PoseGaussian(topology::sample(exact, *rng), cov) : exact);
  };
  for (AreaId i = 0; i + 1 < truth.size(); ++i) add(i, i + 1, kCrossingCov);
  add(11, 0, kAlignedCov);
  add(1, 11, kAlignedCov);
  return m;
}

// The false loop closure: area 9 taken for area 3 (a look-alike room across
// the block), the measured pose of 3 in 9 off the truth by 3 m, 2 m and
// 0.5 rad, with a fine alignment's small covariance.
void plant_false_closure(HmtMap& m, const std::vector<Pose2D>& truth) {
  m.add_arc_measurement(
      9, 3, PoseGaussian((truth[3] - truth[9]) + Pose2D(3.0, -2.0, 0.5), kAlignedCov));
}

double worst_error_m(const GlobalPoses& g, const std::vector<Pose2D>& truth) {
  double worst = 0.0;
  for (AreaId i = 0; i < truth.size(); ++i)
    worst = std::max(worst, (g.poses.at(i).mean - truth[i]).norm());
  return worst;
}

TEST(RobustPoses, FalseClosureIsSwitchedOffAndTheMapStaysTrue) {
  const std::vector<Pose2D> truth = ring_truth();
  HmtMap m = ring_map(truth, nullptr);
  plant_false_closure(m, truth);
  PoseGraphOptions plain;
  plain.robust = false;
  PoseGraphReport plain_report;
  const GlobalPoses bent = optimize_poses(m, 0, plain, &plain_report);
  EXPECT_GT(worst_error_m(bent, truth), 1.0);
  EXPECT_TRUE(plain_report.outliers.empty());
  EXPECT_EQ(plain_report.tested_arcs, 0);

  PoseGraphReport report;
  const GlobalPoses robust = optimize_poses(m, 0, {}, &report);
  EXPECT_LT(worst_error_m(robust, truth), 0.03);
  for (AreaId i = 0; i < truth.size(); ++i)
    EXPECT_LT(std::fabs(topology::difference(robust.poses.at(i).mean, truth[i])(2)), 0.005)
        << "area " << i;
  ASSERT_EQ(report.outliers.size(), 1u);
  EXPECT_EQ(report.outliers[0].from, 3u);  // stored from < to
  EXPECT_EQ(report.outliers[0].to, 9u);
  EXPECT_GT(report.outliers[0].chi2, 10 * PoseGraphOptions{}.outlier_chi2);
  // The three loop arcs (the chain is never tested); what is left fits.
  EXPECT_EQ(report.tested_arcs, 3);
  EXPECT_LT(report.max_arc_chi2, 1e-6);
  EXPECT_LT(report.final_chi2, 1e-6);
  EXPECT_TRUE(report.converged);
  expect_root_identity(robust);
  for (AreaId i = 1; i < truth.size(); ++i)
    EXPECT_TRUE(topology::is_positive_definite(robust.poses.at(i).cov)) << "area " << i;
}

TEST(RobustPoses, EqualsThePlainEstimateWithoutTheOutlier) {
  // With noisy arcs, the robust estimate of the map with the false closure
  // is the plain estimate of the map without it: the outlier has no pull.
  const std::vector<Pose2D> truth = ring_truth();
  for (uint64_t seed = 1; seed <= 10; ++seed) {
    Random rng(seed);
    const HmtMap clean = ring_map(truth, &rng);
    HmtMap m = clean;
    plant_false_closure(m, truth);
    PoseGraphReport report;
    const GlobalPoses robust = optimize_poses(m, 0, {}, &report);
    PoseGraphOptions plain;
    plain.robust = false;
    const GlobalPoses expected = optimize_poses(clean, 0, plain);
    ASSERT_EQ(report.outliers.size(), 1u) << "seed " << seed;
    for (AreaId i = 0; i < truth.size(); ++i) {
      EXPECT_LT(topology::difference(robust.poses.at(i).mean, expected.poses.at(i).mean)
                    .cwiseAbs().maxCoeff(), 1e-6)
          << "seed " << seed << " area " << i;
      EXPECT_LT((robust.poses.at(i).cov - expected.poses.at(i).cov).cwiseAbs().maxCoeff(), 1e-9)
          << "seed " << seed << " area " << i;
    }
  }
}

TEST(RobustPoses, CorrectClosuresKeepThePlainEstimate) {
  // No outlier: nothing is switched off and the result is the plain least
  // squares bit for bit, on noisy rings and on the six-area loop whose
  // arcs are all loop arcs (no frames, so no chain).
  const std::vector<Pose2D> truth = ring_truth();
  PoseGraphOptions plain;
  plain.robust = false;
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    Random rng(seed);
    for (const HmtMap& m : {ring_map(truth, &rng), noisy_loop(square_loop_truth(), rng)}) {
      PoseGraphReport report;
      const GlobalPoses robust = optimize_poses(m, 0, {}, &report);
      const GlobalPoses expected = optimize_poses(m, 0, plain);
      EXPECT_TRUE(report.outliers.empty()) << "seed " << seed;
      EXPECT_GT(report.tested_arcs, 0) << "seed " << seed;
      EXPECT_GT(report.max_arc_chi2, 0.0) << "seed " << seed;
      EXPECT_LE(report.max_arc_chi2, PoseGraphOptions{}.outlier_chi2) << "seed " << seed;
      for (const auto& [id, p] : expected.poses) {
        EXPECT_EQ(vec(robust.poses.at(id).mean), vec(p.mean)) << "seed " << seed;
        EXPECT_EQ(robust.poses.at(id).cov, p.cov) << "seed " << seed;
      }
    }
  }
}

TEST(RobustPoses, ChainArcsAreNeverSwitchedOff) {
  // One loop whose misfit is the chain's fault (the crossing 5 -> 6 off by
  // 5 m; the chain's own heading uncertainty makes 2 m plausible). In a single loop every arc is predicted by all the others, so
  // geometry cannot say which is wrong; the chain is the metric filter's
  // tracking and is trusted, the closure is the decision that can be wrong
  // and is the one switched off. The estimate is then the chain itself.
  const std::vector<Pose2D> truth = ring_truth();
  HmtMap m = ring_areas(truth);
  for (AreaId i = 0; i + 1 < truth.size(); ++i) {
    Pose2D mean = truth[i + 1] - truth[i];
    if (i == 5) mean = mean + Pose2D(0.0, 5.0, 0.0);
    EXPECT_TRUE(is_chain_arc(m, m.add_arc_measurement(i, i + 1, PoseGaussian(mean, kCrossingCov))));
  }
  const GlobalPoses chain = shortest_path_poses(m, 0);  // the chain alone
  m.add_arc_measurement(11, 0, PoseGaussian(truth[0] - truth[11], kAlignedCov));
  EXPECT_FALSE(is_chain_arc(m, *m.find_arc(0, 11)));
  PoseGraphReport report;
  const GlobalPoses g = optimize_poses(m, 0, {}, &report);
  EXPECT_EQ(report.tested_arcs, 1);
  ASSERT_EQ(report.outliers.size(), 1u);
  EXPECT_EQ(report.outliers[0].from, 0u);
  EXPECT_EQ(report.outliers[0].to, 11u);
  EXPECT_LT(report.final_chi2, 1e-12);
  EXPECT_EQ(report.max_arc_chi2, 0.0);  // nothing left to test
  for (AreaId i = 0; i < truth.size(); ++i)
    EXPECT_LT(topology::difference(g.poses.at(i).mean, chain.poses.at(i).mean).norm(), 1e-9);
}

TEST(RobustPoses, TheStatisticIsTheLoopsMahalanobisDistance) {
  // In a ring with one loop arc, the arc's normalised residual at the
  // estimate is the distance of its mean from the chain's composition
  // under the sum of both covariances (and the floor): what TLCA tests
  // before fusing a closure. Equal to first order: the estimate
  // linearises at the optimum, the composition at the chain.
  const std::vector<Pose2D> truth = ring_truth();
  HmtMap m = ring_areas(truth);
  // Crossings 5 times more certain than kCrossingCov: a loop that a small
  // misfit already fails, so the first-order terms dominate.
  for (AreaId i = 0; i + 1 < truth.size(); ++i)
    m.add_arc_measurement(i, i + 1, PoseGaussian(truth[i + 1] - truth[i], kCrossingCov / 25));
  std::vector<AreaId> chain;
  for (AreaId i = 0; i < 12; ++i) chain.push_back(i);
  const PoseGaussian path = topology::compose_path(m, chain);  // 11 in 0
  m.add_arc_measurement(
      11, 0, PoseGaussian((truth[0] - truth[11]) + Pose2D(0.2, -0.16, 0.016), kAlignedCov));
  // In the arc's stored direction, 0 -> 11, where the floor is added.
  const PoseGaussian closure = m.arc(0, 11);
  for (const auto& [fxy, fth] : {std::pair{0.0, 0.0}, std::pair{0.05, 0.02}}) {
    PoseGraphOptions o;
    o.outlier_floor_xy = fxy;
    o.outlier_floor_theta = fth;
    PoseGraphReport report;
    optimize_poses(m, 0, o, &report);
    const Eigen::Vector3d d = topology::difference(closure.mean, path.mean);
    const Eigen::Matrix3d S =
        closure.cov + path.cov + Eigen::Matrix3d(Eigen::Vector3d(fxy * fxy, fxy * fxy, fth * fth).asDiagonal());
    const double expected = d.dot(S.inverse() * d);
    EXPECT_GT(expected, 2.0);
    EXPECT_NEAR(report.max_arc_chi2, expected, 0.01 * expected) << "floor " << fxy;
  }
}

TEST(OptimizePoses, BadArgumentsThrow) {
  Random rng(1);
  const HmtMap m = noisy_loop(square_loop_truth(), rng);
  EXPECT_THROW(optimize_poses(m, 42), std::invalid_argument);
  EXPECT_THROW(shortest_path_poses(m, 42), std::invalid_argument);
  PoseGraphOptions options;
  options.max_iterations = 0;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
  options = {};
  options.relative_tolerance = 0.0;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
  options.relative_tolerance = NAN;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
  options = {};
  options.outlier_chi2 = 0.0;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
  options.outlier_chi2 = INFINITY;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
  options = {};
  options.outlier_floor_xy = -0.1;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
  options = {};
  options.outlier_floor_theta = NAN;
  EXPECT_THROW(optimize_poses(m, 0, options), std::invalid_argument);
}

}  // namespace
}  // namespace hmt::global_map
