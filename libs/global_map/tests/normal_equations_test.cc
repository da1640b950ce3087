// The sparse normal equations (src/normal_equations.h) against a dense sum
// of J^T Omega J and J^T Omega e, constraint by constraint.
#include "normal_equations.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "hmt/common/random.h"

namespace hmt::global_map {
namespace {

struct Constraint {
  int a, b;  // first columns, -1 for the root
  LinearisedRelativePose l;
  Eigen::Matrix3d omega;
};

Pose2D random_pose(Random& rng) {
  return Pose2D(rng.uniform(-10, 10), rng.uniform(-10, 10), rng.uniform(-3, 3));
}

// A random graph of `poses` variables (the first one the root), where some
// pairs are joined more than once, as an area and a keyframe are by an
// in-area edge and a match.
std::vector<Constraint> random_constraints(int poses, int count, Random& rng) {
  std::vector<Constraint> out;
  for (int k = 0; k < count; ++k) {
    const int va = static_cast<int>(rng.next_u64() % static_cast<uint64_t>(poses));
    int vb = static_cast<int>(rng.next_u64() % static_cast<uint64_t>(poses - 1));
    if (vb >= va) ++vb;
    Eigen::Matrix3d m;
    for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = rng.uniform(-1, 1);
    auto column = [](int v) { return v == 0 ? -1 : 3 * v - 3; };  // variable 0 is the root
    out.push_back({column(va), column(vb),
                   linearise_relative_pose(random_pose(rng), random_pose(rng), random_pose(rng)),
                   m * m.transpose() + Eigen::Matrix3d::Identity()});
  }
  return out;
}

// The normal equations of `cs`, summed `passes` times from clear().
NormalEquations summed(int unknowns, const std::vector<Constraint>& cs, int passes) {
  std::vector<std::pair<int, int>> pairs;
  for (const Constraint& c : cs) pairs.emplace_back(c.a, c.b);
  NormalEquations eq(unknowns, pairs);
  for (int pass = 0; pass < passes; ++pass) {
    eq.clear();
    for (size_t k = 0; k < cs.size(); ++k) eq.add(k, cs[k].l, cs[k].omega);
  }
  return eq;
}

TEST(NormalEquations, EqualTheDenseSumInTheLowerTriangle) {
  Random rng(7);
  const int poses = 12, unknowns = 3 * (poses - 1);
  const std::vector<Constraint> cs = random_constraints(poses, 40, rng);
  // A second pass starts from zero again.
  const NormalEquations eq = summed(unknowns, cs, 2);
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(unknowns + 3, unknowns + 3);  // root first
  Eigen::VectorXd g = Eigen::VectorXd::Zero(unknowns + 3);
  for (const Constraint& c : cs) {
    Eigen::Matrix<double, 3, 6> J;
    J << c.l.d_from, c.l.d_to;
    const int at[2] = {c.a < 0 ? 0 : c.a + 3, c.b < 0 ? 0 : c.b + 3};
    const Eigen::Matrix<double, 6, 6> h = J.transpose() * c.omega * J;
    const Eigen::Matrix<double, 6, 1> v = J.transpose() * c.omega * c.l.residual;
    for (int i = 0; i < 2; ++i) {
      g.segment<3>(at[i]) += v.segment<3>(3 * i);
      for (int j = 0; j < 2; ++j) H.block<3, 3>(at[i], at[j]) += h.block<3, 3>(3 * i, 3 * j);
    }
  }
  const Eigen::MatrixXd want = H.bottomRightCorner(unknowns, unknowns);
  const Eigen::MatrixXd got = Eigen::MatrixXd(eq.H());
  for (int r = 0; r < unknowns; ++r)
    for (int c = 0; c < unknowns; ++c) {
      if (r < c) {
        EXPECT_EQ(got(r, c), 0.0) << "stored above the diagonal at " << r << ", " << c;
      } else {
        EXPECT_NEAR(got(r, c), want(r, c), 1e-9 * (1 + std::abs(want(r, c)))) << r << ", " << c;
      }
    }
  EXPECT_LT((eq.g() - g.tail(unknowns)).norm(), 1e-9 * (1 + g.norm()));
  // Only the lower triangle is stored, in sorted rows.
  for (int c = 0; c < unknowns; ++c)
    for (SparseMatrix::InnerIterator it(eq.H(), c); it; ++it) EXPECT_GE(it.row(), c);
  EXPECT_TRUE(eq.H().isCompressed());
}

TEST(NormalEquations, SolveAsTheDenseSystem) {
  Random rng(11);
  const int poses = 30, unknowns = 3 * (poses - 1);
  const NormalEquations eq = summed(unknowns, random_constraints(poses, 200, rng), 1);
  Cholesky cholesky;
  cholesky.analyzePattern(eq.H());
  factorize(cholesky, eq.H(), "test");
  const Eigen::VectorXd x = cholesky.solve(-eq.g());
  const SparseMatrix full = eq.H().selfadjointView<Eigen::Lower>();
  const Eigen::MatrixXd dense(full);
  EXPECT_LT((dense * x + eq.g()).norm(), 1e-8 * eq.g().norm());
}

TEST(NormalEquations, BadColumnsThrow) {
  EXPECT_THROW(NormalEquations(7, {}), std::invalid_argument);
  EXPECT_THROW(NormalEquations(6, {{0, 1}}), std::invalid_argument);
  EXPECT_THROW(NormalEquations(6, {{0, 6}}), std::invalid_argument);
  EXPECT_THROW(NormalEquations(6, {{-2, 3}}), std::invalid_argument);
  EXPECT_THROW(NormalEquations(6, {{3, 3}}), std::invalid_argument);
  EXPECT_NO_THROW(NormalEquations(6, {{-1, 3}, {0, 3}, {3, 0}}));
}

}  // namespace
}  // namespace hmt::global_map
