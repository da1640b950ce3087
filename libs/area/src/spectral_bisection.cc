#include "hmt/area/spectral_bisection.h"

#include <Spectra/SymEigsSolver.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace hmt::area {
namespace {

// Shift of L + sigma I. Must be far below any lambda_2 we care about (so that
// 1/(lambda_2 + sigma) stays well apart from 1/(lambda_3 + sigma)) and far
// above the rounding in the factorisation (~1e-15): the component along z0,
// amplified by 1/sigma, is projected out after every solve.
constexpr double kShift = 1e-8;

// x -> P (L + sigma I)^-1 P x, for Spectra.
template <class Ldlt>
class DeflatedShiftInvert {
 public:
  using Scalar = double;
  DeflatedShiftInvert(const Ldlt& ldlt, const Eigen::VectorXd& u)
      : ldlt_(ldlt), u_(u), tmp_(u.size()) {}
  Eigen::Index rows() const { return u_.size(); }
  Eigen::Index cols() const { return u_.size(); }
  void perform_op(const double* x_in, double* y_out) const {
    Eigen::Map<const Eigen::VectorXd> x(x_in, u_.size());
    Eigen::Map<Eigen::VectorXd> y(y_out, u_.size());
    tmp_ = x - u_ * u_.dot(x);
    y = ldlt_.solve(tmp_);
    y -= u_ * u_.dot(y);
  }

 private:
  const Ldlt& ldlt_;
  const Eigen::VectorXd& u_;
  mutable Eigen::VectorXd tmp_;
};

// The lower triangle of L + sigma I (L = I - D^-1/2 W D^-1/2), built column
// by column (inner indices of W are sorted within each column).
WeightMatrix shifted_laplacian_lower(const WeightMatrix& W,
                                     const Eigen::VectorXd& s) {
  const Eigen::Index n = W.cols();
  WeightMatrix A(n, n);
  Eigen::VectorXi per_col(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    int c = 1;
    for (WeightMatrix::InnerIterator it(W, j); it; ++it) c += it.row() > j;
    per_col[j] = c;
  }
  A.reserve(per_col);
  for (Eigen::Index j = 0; j < n; ++j) {
    A.insert(j, j) = 1.0 + kShift;
    for (WeightMatrix::InnerIterator it(W, j); it; ++it)
      if (it.row() > j)
        A.insert(it.row(), j) = -it.value() * s[it.row()] * s[j];
  }
  A.makeCompressed();
  return A;
}

// Size of the envelope (profile) of a lower-triangular pattern: an upper
// bound on the fill of its factor without reordering.
size_t envelope(const WeightMatrix& A) {
  const Eigen::Index n = A.cols();
  std::vector<Eigen::Index> first(n);
  for (Eigen::Index i = 0; i < n; ++i) first[i] = i;
  for (Eigen::Index j = n - 1; j >= 0; --j)
    for (WeightMatrix::InnerIterator it(A, j); it; ++it)
      first[it.row()] = std::min(first[it.row()], j);
  size_t e = 0;
  for (Eigen::Index i = 0; i < n; ++i) e += static_cast<size_t>(i - first[i]);
  return e;
}

// D^-1/2 W D^-1/2 z, with s = D^-1/2.
Eigen::VectorXd normalized_product(const WeightMatrix& W,
                                   const Eigen::VectorXd& s,
                                   const Eigen::VectorXd& z) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(z.size());
  for (Eigen::Index j = 0; j < W.outerSize(); ++j)
    for (WeightMatrix::InnerIterator it(W, j); it; ++it)
      if (it.row() != j)
        out[it.row()] += it.value() * s[it.row()] * s[j] * z[j];
  return out;
}

// Lanczos on the deflated shift-invert operator; false if it did not
// converge to an eigenpair of L.
template <class Ldlt>
bool lanczos(const WeightMatrix& W, const Eigen::VectorXd& s, const Ldlt& ldlt,
             const Eigen::VectorXd& u, Fiedler& f) {
  const Eigen::Index n = u.size();
  DeflatedShiftInvert<Ldlt> op(ldlt, u);
  // The target is separated from the rest of the inverted spectrum by the
  // ratio lambda_3 / lambda_2, so a small basis converges in one or two
  // restarts; a larger one with more restarts is the second attempt.
  // Spectra's default start vector is seeded: deterministic.
  const Eigen::Index attempts[2][2] = {{8, 1000}, {40, 5000}};
  for (const auto& at : attempts) {
    const Eigen::Index ncv = std::min<Eigen::Index>(n, at[0]);
    Spectra::SymEigsSolver<DeflatedShiftInvert<Ldlt>> eigs(op, 1, ncv);
    eigs.init();
    eigs.compute(Spectra::SortRule::LargestAlge, at[1], 1e-10);
    if (eigs.info() != Spectra::CompInfo::Successful) continue;
    Eigen::VectorXd z = eigs.eigenvectors(1).col(0);
    z -= u * u.dot(z);
    const double norm = z.norm();
    if (!(norm > 0.5)) continue;  // the Ritz vector was mostly along z0
    z /= norm;
    // The eigenvalue from the Rayleigh quotient of L (exact for the vector
    // we return), and a check that it is an eigenpair: when the complement
    // of z0 is one eigenspace (a complete graph of equal weights) Lanczos
    // breaks down early and the Ritz value alone cannot be trusted.
    const Eigen::VectorXd Mz = normalized_product(W, s, z);
    const double lambda = 1.0 - z.dot(Mz);
    if ((Mz - (1.0 - lambda) * z).norm() > 1e-6) continue;
    f.z = z;
    f.lambda = lambda;
    f.solver = EigenSolver::kLanczos;
    f.iterations = static_cast<int>(eigs.num_iterations());
    return true;
  }
  return false;
}

void require_connected_input(const WeightMatrix& W, const Eigen::VectorXd& d) {
  if (W.rows() != W.cols() || W.cols() < 2)
    throw std::invalid_argument("fiedler_vector: need a square W with n >= 2");
  if (d.minCoeff() <= 0.0)
    throw std::invalid_argument(
        "fiedler_vector: the graph has an isolated node (not connected)");
}

// Fixes the sign (largest-magnitude component positive, first on ties) so
// results do not depend on the solver's start vector, and fills y.
void finish(Fiedler& f, const Eigen::VectorXd& d) {
  Eigen::Index k = 0;
  f.z.cwiseAbs().maxCoeff(&k);
  if (f.z[k] < 0) f.z = -f.z;
  f.y = f.z.cwiseQuotient(d.cwiseSqrt());
}

}  // namespace

const char* to_string(EigenSolver s) {
  switch (s) {
    case EigenSolver::kNone:
      return "none";
    case EigenSolver::kComponents:
      return "components";
    case EigenSolver::kDense:
      return "dense";
    case EigenSolver::kLanczos:
      return "lanczos";
  }
  return "none";
}

Fiedler fiedler_vector_dense(const WeightMatrix& W) {
  const Eigen::VectorXd d = degrees(W);
  require_connected_input(W, d);
  const Eigen::Index n = W.cols();
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  Eigen::MatrixXd L = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index j = 0; j < W.outerSize(); ++j)
    for (WeightMatrix::InnerIterator it(W, j); it; ++it)
      if (it.row() != j) L(it.row(), j) -= it.value() * s[it.row()] * s[j];
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(L);
  if (es.info() != Eigen::Success)
    throw std::runtime_error("fiedler_vector_dense: eigen solver failed");
  Fiedler f;
  f.z = es.eigenvectors().col(1);
  f.lambda = es.eigenvalues()[1];
  f.solver = EigenSolver::kDense;
  finish(f, d);
  return f;
}

Fiedler fiedler_vector_lanczos(const WeightMatrix& W) {
  const Eigen::VectorXd d = degrees(W);
  require_connected_input(W, d);
  const Eigen::Index n = W.cols();
  if (n < 3)
    throw std::invalid_argument("fiedler_vector_lanczos: needs n >= 3");
  const Eigen::VectorXd s = d.cwiseSqrt().cwiseInverse();
  const WeightMatrix A = shifted_laplacian_lower(W, s);
  const Eigen::VectorXd u = d.cwiseSqrt().normalized();
  Fiedler f;
  bool ok = false;
  // Keyframes in time order give a banded W (a keyframe overlaps those just
  // before and after it), whose factor has no fill at all in the natural
  // order, and the AMD analysis would cost more than the factorisation. When
  // the envelope is large (revisits far apart in time) AMD is worth it.
  if (envelope(A) <= 3 * static_cast<size_t>(A.nonZeros())) {
    Eigen::SimplicialLDLT<WeightMatrix, Eigen::Lower,
                          Eigen::NaturalOrdering<int>>
        ldlt(A);
    ok = ldlt.info() == Eigen::Success && lanczos(W, s, ldlt, u, f);
  } else {
    Eigen::SimplicialLDLT<WeightMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>
        ldlt(A);
    ok = ldlt.info() == Eigen::Success && lanczos(W, s, ldlt, u, f);
  }
  if (!ok) {
    // Not expected for a connected graph; a dense solve is slow for big n
    // but correct, and the caller can see it happened.
    return fiedler_vector_dense(W);
  }
  finish(f, d);
  return f;
}

Fiedler fiedler_vector(const WeightMatrix& W) {
  return W.cols() <= kDenseMaxNodes ? fiedler_vector_dense(W)
                                    : fiedler_vector_lanczos(W);
}

std::vector<char> split_at(const Eigen::VectorXd& y, double threshold) {
  std::vector<char> in_a(y.size());
  for (Eigen::Index i = 0; i < y.size(); ++i) in_a[i] = y[i] > threshold;
  return in_a;
}

std::vector<char> sweep_split(const WeightMatrix& W, const Eigen::VectorXd& y,
                              int min_size) {
  const int n = static_cast<int>(y.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return y[a] < y[b]; });
  const Eigen::VectorXd d = degrees(W);
  const double vol = d.sum();
  std::vector<char> in_s(n, 0);
  double cut = 0.0, vol_s = 0.0, best = 0.0;
  int best_k = -1;
  for (int k = 1; k < n; ++k) {
    const int v = order[k - 1];
    double w_to_s = 0.0;
    for (WeightMatrix::InnerIterator it(W, v); it; ++it)
      if (it.row() != v && in_s[it.row()]) w_to_s += it.value();
    in_s[v] = 1;
    // v's edges into S stop being cut; its edges to the rest start being cut.
    cut += d[v] - 2.0 * w_to_s;
    vol_s += d[v];
    if (k < min_size || n - k < min_size) continue;
    const double c = std::max(cut, 0.0);
    double nc = 0.0;
    if (c > 0.0) nc = c / vol_s + c / (vol - vol_s);
    if (best_k < 0 || nc < best) {
      best = nc;
      best_k = k;
    }
  }
  std::vector<char> in_a;
  if (best_k < 0) return in_a;
  in_a.assign(n, 0);
  for (int k = 0; k < best_k; ++k) in_a[order[k]] = 1;
  return in_a;
}

Bisection spectral_bisection(const WeightMatrix& W,
                             const BisectionOptions& options) {
  if (W.rows() != W.cols())
    throw std::invalid_argument("spectral_bisection: W is not square");
  Bisection r;
  const int n = static_cast<int>(W.cols());
  if (n < 2) return r;

  std::vector<char> in_a;
  int ncomp = 0;
  const std::vector<int> comp = connected_components(W, &ncomp);
  if (ncomp > 1) {
    // Zero-Ncut split: the largest component (the one with the smallest
    // node on ties) against all the others.
    std::vector<int> size(ncomp, 0);
    for (int c : comp) ++size[c];
    const int big = static_cast<int>(
        std::max_element(size.begin(), size.end()) - size.begin());
    in_a.resize(n);
    for (int i = 0; i < n; ++i) in_a[i] = comp[i] == big;
    r.fiedler.solver = EigenSolver::kComponents;
  } else {
    r.fiedler = fiedler_vector(W);
    const Eigen::VectorXd& y = r.fiedler.y;
    switch (options.split_method) {
      case SplitMethod::kMean:
        in_a = split_at(y, y.mean());
        break;
      case SplitMethod::kSign:
        in_a = split_at(y, 0.0);
        break;
      case SplitMethod::kSweep:
        in_a = sweep_split(W, y, options.min_cluster_size);
        break;
    }
    if (!in_a.empty()) {
      const auto na = std::count(in_a.begin(), in_a.end(), 1);
      if (na == 0 || na == n)
        in_a = sweep_split(W, y, options.min_cluster_size);
    }
    if (in_a.empty()) return r;
  }
  if (!in_a[0])
    for (auto& v : in_a) v = !v;
  for (int i = 0; i < n; ++i) (in_a[i] ? r.a : r.b).push_back(i);
  r.ncut = normalized_cut(W, in_a);
  r.valid = true;
  return r;
}

}  // namespace hmt::area
