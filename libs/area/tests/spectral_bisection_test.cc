#include "hmt/area/spectral_bisection.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "test_graphs.h"

namespace hmt::area {
namespace {

using testing::from_triplets;

// Reference: dense normalized Laplacian, second-smallest eigenpair.
std::pair<double, Eigen::VectorXd> dense_reference(const WeightMatrix& W) {
  const Eigen::MatrixXd Wd = Eigen::MatrixXd(W);
  const Eigen::VectorXd d = Wd.rowwise().sum();
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd L = Eigen::MatrixXd::Identity(W.rows(), W.cols()) -
                            s.asDiagonal() * Wd * s.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(L);
  return {es.eigenvalues()[1], es.eigenvectors().col(1)};
}

TEST(area_SpectralBisection, LanczosMatchesDenseSolverOnRandomConnectedGraphs) {
  Random rng(11);
  for (int n : {30, 45, 60, 80, 100, 130, 160, 200}) {
    for (int rep = 0; rep < 2; ++rep) {
      const WeightMatrix W =
          testing::random_connected(n, rng.uniform(0.02, 0.2), rng);
      const Fiedler f = fiedler_vector_lanczos(W);
      ASSERT_EQ(f.solver, EigenSolver::kLanczos) << n;
      const auto [lambda, z] = dense_reference(W);
      const double cosine = std::fabs(f.z.dot(z)) / (f.z.norm() * z.norm());
      EXPECT_GT(cosine, 0.999) << "n=" << n;
      EXPECT_NEAR(f.lambda, lambda, 1e-8 + 1e-6 * lambda) << "n=" << n;
      // y = D^-1/2 z is D-orthogonal to the constant vector (Eq. 10).
      const Eigen::VectorXd d = degrees(W);
      EXPECT_NEAR(d.dot(f.y), 0.0, 1e-8 * d.sum() * f.y.cwiseAbs().maxCoeff());
    }
  }
}

TEST(area_SpectralBisection, LanczosHandlesTinyAlgebraicConnectivity) {
  // A long path: lambda_2 ~ 1e-4, where Lanczos on the largest eigenpairs of
  // D^-1/2 W D^-1/2 struggles.
  std::vector<Eigen::Triplet<double>> t;
  const int n = 300;
  for (int i = 0; i + 1 < n; ++i) t.emplace_back(i, i + 1, 1.0);
  const WeightMatrix W = from_triplets(n, t);
  const Fiedler f = fiedler_vector_lanczos(W);
  EXPECT_EQ(f.solver, EigenSolver::kLanczos);
  const auto [lambda, z] = dense_reference(W);
  EXPECT_GT(std::fabs(f.z.dot(z)), 0.999);
  EXPECT_NEAR(f.lambda, lambda, 1e-9);
  // The path splits in the middle.
  const Bisection b = spectral_bisection(W);
  EXPECT_EQ(b.a.size(), 150u);
  EXPECT_EQ(b.a.front(), 0);
  EXPECT_EQ(b.a.back(), 149);
}

TEST(area_SpectralBisection, DegenerateSpectraStillGiveAnEigenpair) {
  for (int n : {9, 20, 64}) {
    // Complete graph of equal weights: every vector orthogonal to z0 is an
    // eigenvector with lambda = n/(n-1) (Lanczos breaks down at once), and
    // every split has Ncut n/(n-1).
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) t.emplace_back(i, j, 1.0);
    const WeightMatrix K = from_triplets(n, t);
    const Fiedler fk = fiedler_vector_lanczos(K);
    EXPECT_NEAR(fk.lambda, n / (n - 1.0), 1e-9) << n;
    EXPECT_NEAR(fk.z.norm(), 1.0, 1e-12);
    const Bisection bk = spectral_bisection(K);
    ASSERT_TRUE(bk.valid);
    EXPECT_NEAR(bk.ncut, n / (n - 1.0), 1e-12);
    // Ring: lambda_2 = 1 - cos(2 pi / n), twice; the best split is two arcs.
    t.clear();
    for (int i = 0; i < n; ++i) t.emplace_back(i, (i + 1) % n, 1.0);
    const WeightMatrix R = from_triplets(n, t);
    EXPECT_NEAR(fiedler_vector_lanczos(R).lambda,
                1.0 - std::cos(2.0 * M_PI / n), 1e-9);
    const Bisection br = spectral_bisection(R, {SplitMethod::kSweep, 1});
    // Two arcs of k and n - k nodes: cut 2, assoc 2k and 2(n - k).
    EXPECT_NEAR(br.ncut, 1.0 / (n / 2) + 1.0 / (n - n / 2), 1e-12) << n;
  }
}

TEST(area_SpectralBisection, SmallGraphsUseTheDenseSolver) {
  const WeightMatrix W =
      from_triplets(4, {{0, 1, 1.0}, {1, 2, 0.1}, {2, 3, 1.0}});
  EXPECT_EQ(fiedler_vector(W).solver, EigenSolver::kDense);
  const Bisection b = spectral_bisection(W);
  ASSERT_TRUE(b.valid);
  EXPECT_EQ(b.a, (std::vector<int>{0, 1}));
  EXPECT_EQ(b.b, (std::vector<int>{2, 3}));
  // cut 0.1; assoc({0,1}) = 1 + 1.1 = assoc({2,3}).
  EXPECT_NEAR(b.ncut, 2.0 * 0.1 / 2.1, 1e-12);
  Random rng(3);
  const WeightMatrix big =
      testing::random_connected(kDenseMaxNodes + 1, 0.3, rng);
  EXPECT_EQ(fiedler_vector(big).solver, EigenSolver::kLanczos);
}

TEST(area_SpectralBisection,
     DisconnectedGraphSplitsAlongComponentsWithZeroNcut) {
  // Components {0,1,2}, {3,4} and the isolated node 5.
  const WeightMatrix W =
      from_triplets(6, {{0, 1, 1.0}, {1, 2, 1.0}, {0, 2, 0.5}, {3, 4, 1.0}});
  const Bisection b = spectral_bisection(W);
  ASSERT_TRUE(b.valid);
  EXPECT_EQ(b.fiedler.solver, EigenSolver::kComponents);
  EXPECT_DOUBLE_EQ(b.ncut, 0.0);
  EXPECT_EQ(b.a, (std::vector<int>{0, 1, 2}));  // the largest component
  EXPECT_EQ(b.b, (std::vector<int>{3, 4, 5}));
  // Only isolated nodes.
  const WeightMatrix E(3, 3);
  const Bisection e = spectral_bisection(E);
  ASSERT_TRUE(e.valid);
  EXPECT_DOUBLE_EQ(e.ncut, 0.0);
  EXPECT_EQ(e.a, (std::vector<int>{0}));
}

TEST(area_SpectralBisection, NothingToSplitBelowTwoNodes) {
  EXPECT_FALSE(spectral_bisection(WeightMatrix(1, 1)).valid);
  EXPECT_FALSE(spectral_bisection(WeightMatrix(0, 0)).valid);
  EXPECT_THROW(fiedler_vector(WeightMatrix(3, 3)), std::invalid_argument);
}

TEST(area_SpectralBisection, ReportedNcutIsExactAndInRange) {
  Random rng(5);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 2 + static_cast<int>(rng.uniform() * 60);
    const WeightMatrix W =
        testing::random_graph(n, rng.uniform(0.05, 0.6), rng);
    for (SplitMethod m :
         {SplitMethod::kMean, SplitMethod::kSign, SplitMethod::kSweep}) {
      const Bisection b = spectral_bisection(W, {m, 1});
      ASSERT_TRUE(b.valid);
      EXPECT_FALSE(b.a.empty());
      EXPECT_FALSE(b.b.empty());
      EXPECT_EQ(b.a.size() + b.b.size(), static_cast<size_t>(n));
      EXPECT_TRUE(std::is_sorted(b.a.begin(), b.a.end()));
      EXPECT_TRUE(std::is_sorted(b.b.begin(), b.b.end()));
      EXPECT_EQ(b.a.front(), 0);
      std::vector<char> in_a(n, 0);
      for (int i : b.a) in_a[i] = 1;
      EXPECT_DOUBLE_EQ(b.ncut, normalized_cut(W, in_a));
      EXPECT_GE(b.ncut, 0.0);
      EXPECT_LE(b.ncut, 2.0 + 1e-12);
    }
  }
}

TEST(area_SpectralBisection, SweepFindsTheLeastNcutThresholdAndBeatsMean) {
  Random rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    const WeightMatrix W = testing::random_connected(40, 0.15, rng);
    const Bisection mean = spectral_bisection(W, {SplitMethod::kMean, 1});
    const Bisection sweep = spectral_bisection(W, {SplitMethod::kSweep, 1});
    EXPECT_LE(sweep.ncut, mean.ncut + 1e-12);
    // Brute force over the thresholds between sorted components.
    const Eigen::VectorXd& y = sweep.fiedler.y;
    std::vector<double> v(y.data(), y.data() + y.size());
    std::sort(v.begin(), v.end());
    double best = 3.0;
    for (size_t k = 0; k + 1 < v.size(); ++k) {
      if (v[k] == v[k + 1]) continue;
      std::vector<char> in_a(40);
      for (int i = 0; i < 40; ++i) in_a[i] = y[i] <= v[k];
      best = std::min(best, normalized_cut(W, in_a));
    }
    EXPECT_NEAR(sweep.ncut, best, 1e-12);
  }
}

TEST(area_SpectralBisection, SweepHonoursTheMinimumSize) {
  // A pendant node hanging by a weak edge: the best sweep split isolates it,
  // unless each side must hold 3 nodes.
  Random rng(1);
  WeightMatrix W = testing::blocks({12}, 0.0, 0, rng);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < W.outerSize(); ++j)
    for (WeightMatrix::InnerIterator it(W, j); it; ++it)
      if (it.row() < j) t.emplace_back(it.row(), j, it.value());
  t.emplace_back(11, 12, 1e-3);
  W = from_triplets(13, t);
  const Bisection free_split = spectral_bisection(W, {SplitMethod::kSweep, 1});
  EXPECT_EQ(free_split.b, (std::vector<int>{12}));
  const Bisection min3 = spectral_bisection(W, {SplitMethod::kSweep, 3});
  ASSERT_TRUE(min3.valid);
  EXPECT_GE(min3.a.size(), 3u);
  EXPECT_GE(min3.b.size(), 3u);
  EXPECT_FALSE(spectral_bisection(W, {SplitMethod::kSweep, 7}).valid);
}

}  // namespace
}  // namespace hmt::area
