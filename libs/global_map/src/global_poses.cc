#include "hmt/global_map/global_poses.h"

#include <Eigen/CholmodSupport>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "hmt/topology/shortest_paths.h"
#include "normal_equations.h"
#include "relative_pose_factor.h"

namespace hmt::global_map {
namespace {

using topology::Arc;
using topology::HmtMap;
using topology::PoseGaussian;

// A Gauss-Newton step is a descent direction, so some fraction of it lowers
// chi2 unless the estimate already sits at a minimum to rounding; halving
// this many times (down to 1/1024 of the step) tells the two apart.
constexpr int kMaxStepHalvings = 10;

// Below this smallest eigenvalue of the whitened residual covariance
// L^-1 (Sigma_ab - J P J^T) L^-T (L L^T = Sigma_ab), the arc's redundancy
// number in geodesy, in (0, 1]: the rest of the map does not predict the
// arc (a bridge gives 0 to rounding), so its residual is zero whatever its
// mean and it cannot be tested. 1e-6 is a prediction a thousand times less
// certain (in standard deviation) than the arc, far below any real loop.
constexpr double kMinRedundancy = 1e-6;

void require_root(const HmtMap& map, AreaId root, const char* who) {
  if (!map.has_area(root))
    throw std::invalid_argument(std::string(who) + ": unknown root area " +
                                std::to_string(root));
}

void require_valid(const PoseGraphOptions& options) {
  if (options.max_iterations < 1)
    throw std::invalid_argument("optimize_poses: max_iterations must be >= 1");
  if (!(options.relative_tolerance > 0.0 && options.relative_tolerance < 1.0))
    throw std::invalid_argument(
        "optimize_poses: relative_tolerance must be in (0, 1)");
  if (!(options.outlier_chi2 > 0.0 && std::isfinite(options.outlier_chi2)))
    throw std::invalid_argument(
        "optimize_poses: outlier_chi2 must be positive and finite");
  if (!(options.outlier_floor_xy >= 0.0 && std::isfinite(options.outlier_floor_xy)) ||
      !(options.outlier_floor_theta >= 0.0 && std::isfinite(options.outlier_floor_theta)))
    throw std::invalid_argument(
        "optimize_poses: outlier_floor_xy and outlier_floor_theta must be >= 0 and finite");
}

// An arc's residual and Jacobians are those of relative_pose_factor.h.

// The unknowns of the least-squares problem: every reachable area but the
// root, ascending by id, three columns each. The root has no column (it is
// the fixed gauge), marked by -1.
struct Unknowns {
  std::vector<AreaId> areas;
  std::map<AreaId, int> column;  // area -> first column, -1 for the root

  int size() const { return 3 * static_cast<int>(areas.size()); }
};

Unknowns unknowns_of(const GlobalPoses& poses) {
  Unknowns u;
  for (const auto& kv : poses.poses) {
    if (kv.first == poses.root) {
      u.column[kv.first] = -1;
      continue;
    }
    u.column[kv.first] = u.size();
    u.areas.push_back(kv.first);
  }
  return u;
}

// The arcs between reachable areas (both ends reachable or neither, since
// an arc joins its ends), in the map's (from, to) order.
std::vector<const Arc*> arcs_within(const HmtMap& map,
                                    const GlobalPoses& poses) {
  std::vector<const Arc*> arcs;
  for (const auto& kv : map.arcs())
    if (poses.poses.count(kv.first.first) && poses.poses.count(kv.first.second))
      arcs.push_back(&kv.second);
  return arcs;
}

Eigen::Matrix3d information_of(const Arc& arc) {
  return arc.pose.cov.inverse();
}

double chi2_of(const std::vector<const Arc*>& arcs, const GlobalPoses& poses) {
  double sum = 0.0;
  for (const Arc* arc : arcs) {
    const Eigen::Vector3d e = arc_residual(*arc, poses);
    sum += e.dot(information_of(*arc) * e);
  }
  return sum;
}

// The pattern of the normal equations of `arcs` (the root's blocks left
// out).
NormalEquations pattern_of(const std::vector<const Arc*>& arcs, const Unknowns& u) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(arcs.size());
  for (const Arc* arc : arcs) pairs.emplace_back(u.column.at(arc->from), u.column.at(arc->to));
  return NormalEquations(u.size(), pairs);
}

// The normal equations H dx = -g of chi2 linearised at `poses`, into `eq`
// (built by pattern_of()).
void linearise(const std::vector<const Arc*>& arcs, const GlobalPoses& poses,
               NormalEquations* eq) {
  eq->clear();
  for (size_t k = 0; k < arcs.size(); ++k)
    eq->add(k,
            linearise_relative_pose(poses.poses.at(arcs[k]->from).mean,
                                    poses.poses.at(arcs[k]->to).mean, arcs[k]->pose.mean),
            information_of(*arcs[k]));
}

GlobalPoses moved(const GlobalPoses& poses, const Unknowns& u,
                  const Eigen::VectorXd& step) {
  GlobalPoses out = poses;
  for (const AreaId id : u.areas) {
    const int k = u.column.at(id);
    Pose2D& p = out.poses.at(id).mean;
    p = Pose2D(p.x + step(k), p.y + step(k + 1),
               wrap_angle(p.theta + step(k + 2)));
  }
  return out;
}

// Takes the Gauss-Newton step, or the largest halving of it that does not
// raise chi2. Returns false (and leaves `poses` alone) if none does.
bool take_step(const std::vector<const Arc*>& arcs, const Unknowns& u,
               const Eigen::VectorXd& step, GlobalPoses* poses,
               double* chi2_now) {
  double fraction = 1.0;
  for (int k = 0; k <= kMaxStepHalvings; ++k, fraction *= 0.5) {
    GlobalPoses candidate = moved(*poses, u, fraction * step);
    const double c = chi2_of(arcs, candidate);
    if (c <= *chi2_now) {
      *poses = std::move(candidate);
      *chi2_now = c;
      return true;
    }
  }
  return false;
}

// The marginal covariance of every unknown area: the 3x3 diagonal blocks of
// H^-1, one triangular solve pair per area with the existing factor.
void set_marginal_covariances(const Cholesky& cholesky, const Unknowns& u,
                              GlobalPoses* poses) {
  for (const AreaId id : u.areas) {
    const int k = u.column.at(id);
    Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(u.size(), 3);
    unit.block<3, 3>(k, 0).setIdentity();
    const Eigen::MatrixXd columns = cholesky.solve(unit);
    const Eigen::Matrix3d block = columns.block<3, 3>(k, 0);
    Eigen::Matrix3d& cov = poses->poses.at(id).cov;
    cov = 0.5 * (block + block.transpose());
    if (!topology::is_positive_definite(cov))
      throw std::runtime_error("optimize_poses: the covariance of area " +
                               std::to_string(id) +
                               " is not positive definite");
  }
}

// Gauss-Newton over `arcs` from `poses` until the relative change of chi2
// is below the tolerance or the iterations (counted over every solve in
// `r`) run out; leaves `cholesky` factorised at the final estimate. The
// pattern is analysed here, once per solve (it changes when an arc is
// switched off; CHOLMOD frees the previous analysis).
void least_squares(const std::vector<const Arc*>& arcs, const Unknowns& u,
                   const PoseGraphOptions& options, Cholesky* cholesky,
                   GlobalPoses* poses, double* chi2_now, PoseGraphReport* r) {
  NormalEquations eq = pattern_of(arcs, u);
  cholesky->analyzePattern(eq.H());
  r->converged = false;
  for (int k = 0; k < options.max_iterations; ++k) {
    linearise(arcs, *poses, &eq);
    factorize(*cholesky, eq.H(), "optimize_poses");
    const Eigen::VectorXd step = cholesky->solve(-eq.g());
    ++r->iterations;
    const double before = *chi2_now;
    if (!take_step(arcs, u, step, poses, chi2_now) ||
        before - *chi2_now <= options.relative_tolerance * before) {
      r->converged = true;
      break;
    }
  }
  // The information matrix at the final estimate, for the covariances and
  // the outlier test.
  linearise(arcs, *poses, &eq);
  factorize(*cholesky, eq.H(), "optimize_poses");
}

// The normalised residual of one arc (see the header): e^T (Sigma_ab -
// J P J^T)^-1 e, or nothing when the arc has no redundancy.
std::optional<double> normalised_residual(const Arc& arc,
                                          const GlobalPoses& poses,
                                          const Unknowns& u,
                                          const Cholesky& cholesky) {
  const LinearisedRelativePose l = linearise_relative_pose(
      poses.poses.at(arc.from).mean, poses.poses.at(arc.to).mean, arc.pose.mean);
  // The columns of H^-1 of the ends that are unknowns (not the root).
  struct End {
    int column;
    const Eigen::Matrix3d* jacobian;
  };
  std::vector<End> ends;
  for (const End e : {End{u.column.at(arc.from), &l.d_from},
                      End{u.column.at(arc.to), &l.d_to}})
    if (e.column >= 0) ends.push_back(e);
  Eigen::MatrixXd unit = Eigen::MatrixXd::Zero(u.size(), 3 * ends.size());
  for (size_t i = 0; i < ends.size(); ++i)
    unit.block<3, 3>(ends[i].column, 3 * i).setIdentity();
  const Eigen::MatrixXd columns = cholesky.solve(unit);
  Eigen::Matrix3d predicted = Eigen::Matrix3d::Zero();  // J P J^T
  for (size_t i = 0; i < ends.size(); ++i)
    for (size_t j = 0; j < ends.size(); ++j)
      predicted += *ends[i].jacobian *
                   columns.block<3, 3>(ends[i].column, 3 * j) *
                   ends[j].jacobian->transpose();
  const Eigen::Matrix3d residual_cov = arc.pose.cov - predicted;
  // Whitened by the arc's own covariance, the eigenvalues are the arc's
  // redundancy numbers, in [0, 1].
  const Eigen::Matrix3d L = arc.pose.cov.llt().matrixL();
  const Eigen::Matrix3d Linv = L.inverse();
  Eigen::Matrix3d W = Linv * residual_cov * Linv.transpose();
  W = 0.5 * (W + W.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(W);
  if (!(eig.eigenvalues().minCoeff() > kMinRedundancy)) return std::nullopt;
  const Eigen::Vector3d z = eig.eigenvectors().transpose() * (Linv * l.residual);
  return z.cwiseAbs2().cwiseQuotient(eig.eigenvalues()).sum();
}

struct ArcTests {
  int tested = 0;
  const Arc* worst = nullptr;  // largest normalised residual (first on ties)
  double worst_chi2 = 0.0;
};

// The test of the loop arcs among `arcs` (see the header): in the test's
// model, where every loop arc's covariance has the floor F added, fitted
// by least squares from `poses`. `worst` is one of `arcs`.
ArcTests test_loop_arcs(const HmtMap& map, const std::vector<const Arc*>& arcs,
                        const GlobalPoses& poses, const Unknowns& u,
                        const PoseGraphOptions& options) {
  const double fxy = options.outlier_floor_xy * options.outlier_floor_xy;
  const double fth = options.outlier_floor_theta * options.outlier_floor_theta;
  const Eigen::Matrix3d floor = Eigen::Vector3d(fxy, fxy, fth).asDiagonal();
  std::vector<Arc> model;
  std::vector<char> loop;
  model.reserve(arcs.size());
  for (const Arc* arc : arcs) {
    model.push_back(*arc);
    loop.push_back(!is_chain_arc(map, *arc));
    if (loop.back()) model.back().pose.cov += floor;
  }
  std::vector<const Arc*> model_arcs;
  for (const Arc& arc : model) model_arcs.push_back(&arc);
  GlobalPoses fitted = poses;
  double chi2_fitted = chi2_of(model_arcs, fitted);
  PoseGraphReport scratch;  // the test's own fit is not the estimate's
  Cholesky cholesky;
  least_squares(model_arcs, u, options, &cholesky, &fitted, &chi2_fitted, &scratch);

  ArcTests t;
  for (size_t i = 0; i < model.size(); ++i) {
    if (!loop[i]) continue;
    const std::optional<double> w = normalised_residual(model[i], fitted, u, cholesky);
    if (!w) continue;
    ++t.tested;
    if (!t.worst || *w > t.worst_chi2) {
      t.worst = arcs[i];
      t.worst_chi2 = *w;
    }
  }
  return t;
}

// The shortest-path tree over the arcs of `map` but those in `off`, with
// the same reachable areas as `before` (only arcs with redundancy are
// switched off, so there is always another path).
GlobalPoses restarted(const HmtMap& map,
                      const std::set<std::pair<AreaId, AreaId>>& off,
                      const GlobalPoses& before) {
  HmtMap graph;
  for (const AreaId id : map.area_ids()) graph.add_area(id);
  for (const auto& [ends, arc] : map.arcs())
    if (!off.count(ends)) graph.set_arc(arc);
  GlobalPoses tree = shortest_path_poses(graph, before.root);
  if (tree.poses.size() != before.poses.size())
    throw std::logic_error(
        "optimize_poses: switching off an outlier disconnected the map");
  return tree;
}

}  // namespace

GlobalPoses shortest_path_poses(const HmtMap& map, AreaId root) {
  require_root(map, root, "shortest_path_poses");
  const topology::PathTree tree = topology::shortest_paths(map, root);
  GlobalPoses out;
  out.root = root;
  for (const AreaId id : map.area_ids()) {
    const auto it = tree.nodes.find(id);
    if (it == tree.nodes.end())
      out.unreachable.push_back(id);
    else
      out.poses.emplace(id, it->second.pose);
  }
  return out;
}

GlobalPoses optimize_poses(const HmtMap& map, AreaId root,
                           const PoseGraphOptions& options,
                           PoseGraphReport* report) {
  require_root(map, root, "optimize_poses");
  require_valid(options);
  GlobalPoses poses = shortest_path_poses(map, root);
  const Unknowns u = unknowns_of(poses);
  std::vector<const Arc*> arcs = arcs_within(map, poses);

  PoseGraphReport r;
  double chi2_now = chi2_of(arcs, poses);
  r.initial_chi2 = chi2_now;
  if (u.areas.empty()) {  // the root alone: nothing to estimate
    r.final_chi2 = chi2_now;
    r.converged = true;
    if (report) *report = r;
    return poses;
  }

  Cholesky cholesky;
  least_squares(arcs, u, options, &cholesky, &poses, &chi2_now, &r);
  if (options.robust) {
    std::set<std::pair<AreaId, AreaId>> off;
    for (bool first = true;; first = false) {
      const ArcTests tests = test_loop_arcs(map, arcs, poses, u, options);
      if (first) r.tested_arcs = tests.tested;
      r.max_arc_chi2 = tests.worst ? tests.worst_chi2 : 0.0;
      if (!tests.worst || tests.worst_chi2 <= options.outlier_chi2) break;
      // The worst arc goes; the rest is solved again from scratch, from
      // the tree of the arcs that remain (the current estimate is bent by
      // the outlier, possibly by tens of degrees).
      r.outliers.push_back({tests.worst->from, tests.worst->to, tests.worst_chi2});
      off.emplace(tests.worst->from, tests.worst->to);
      poses = restarted(map, off, poses);
      arcs.erase(std::find(arcs.begin(), arcs.end(), tests.worst));
      chi2_now = chi2_of(arcs, poses);
      least_squares(arcs, u, options, &cholesky, &poses, &chi2_now, &r);
    }
  }
  r.final_chi2 = chi2_now;
  set_marginal_covariances(cholesky, u, &poses);
  if (report) *report = r;
  return poses;
}

bool is_chain_arc(const HmtMap& map, const Arc& arc) {
  return map.area(arc.to).frame.parent == arc.from ||
         map.area(arc.from).frame.parent == arc.to;
}

Eigen::Vector3d arc_residual(const Arc& arc, const GlobalPoses& poses) {
  return relative_pose_residual(poses.poses.at(arc.from).mean, poses.poses.at(arc.to).mean,
                     arc.pose.mean);
}

double chi2(const HmtMap& map, const GlobalPoses& poses) {
  return chi2_of(arcs_within(map, poses), poses);
}

}  // namespace hmt::global_map
