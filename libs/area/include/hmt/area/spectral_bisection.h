// Spectral bisection of a weighted graph under the normalized cut
// (Shi & Malik; 000 Sec. 2.2, Eq. 8-11).
//
// The relaxed min-Ncut indicator y solves (D - W) y = lambda D y; with
// z = D^1/2 y it is the eigenvector of the normalized Laplacian
//   L = I - D^-1/2 W D^-1/2
// for its second-smallest eigenvalue (the smallest is 0 with z0 = D^1/2 1).
//
// How z is computed (fiedler_vector): Lanczos (Spectra's SymEigsSolver) on the
// deflated shift-invert operator
//   x -> P (L + sigma I)^-1 P x,   P = I - u u^T,  u = z0 / |z0|,
// whose largest eigenvalue is 1 / (lambda_2 + sigma). L + sigma I is factored
// once by a sparse LDL^T (Eigen::SimplicialLDLT: in the given node order when
// its envelope is small, as for keyframes in time order, else with an AMD
// fill-reducing ordering); no dense matrix is ever formed. The eigenvalue is
// the Rayleigh quotient of the returned vector, which is checked to be an
// eigenvector of L. Shift-invert is used rather than Lanczos on the
// largest eigenpairs of D^-1/2 W D^-1/2 because the interesting graphs are
// exactly those with a tiny lambda_2 (weakly joined areas, long corridors):
// there the top eigenvalues of D^-1/2 W D^-1/2 crowd near 1 and plain Lanczos
// needs hundreds of restarts, whereas after the inversion lambda_2 and
// lambda_3 are separated by their ratio and a few iterations suffice.
// Deflating the known z0 lets us ask for a single eigenpair.
//
// For n <= kDenseMaxNodes a dense Eigen::SelfAdjointEigenSolver is used: a
// Lanczos basis needs ncv > nev vectors and several more to restart well, so
// for a handful of nodes it cannot work as intended, and a dense solve of a
// tiny matrix is cheaper anyway. The dense path is also the fall-back should
// Lanczos fail to converge (reported in Fiedler::solver).
//
// Graphs that are not connected (including isolated, zero-degree nodes) are
// not handed to the eigen solver (D^-1/2 does not exist and the eigenvalue 0
// is repeated): they have a zero-Ncut split along components, which is
// returned directly.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "hmt/area/area_options.h"
#include "hmt/area/ncut.h"

namespace hmt::area {

constexpr int kDenseMaxNodes = 8;

enum class EigenSolver { kNone, kComponents, kDense, kLanczos };
const char* to_string(EigenSolver s);

struct Fiedler {
  Eigen::VectorXd z;    // unit eigenvector of L for lambda
  Eigen::VectorXd y;    // D^-1/2 z, the relaxed indicator of Eq. 8-10
  double lambda = 0.0;  // second-smallest eigenvalue of L
  EigenSolver solver = EigenSolver::kNone;
  int iterations = 0;  // Lanczos restarts (0 for dense)
};

// W must be connected, n >= 2, symmetric with non-negative weights (see
// check_weight_matrix). Dispatches on kDenseMaxNodes.
Fiedler fiedler_vector(const WeightMatrix& W);
// The two paths, exposed for tests and benchmarks.
Fiedler fiedler_vector_lanczos(const WeightMatrix& W);  // needs n >= 3
Fiedler fiedler_vector_dense(const WeightMatrix& W);

struct BisectionOptions {
  SplitMethod split_method = SplitMethod::kMean;
  // The sweep only considers splits with at least this many nodes per side.
  // (Mean and sign splits are not altered; the caller decides whether a
  // small side is acceptable.)
  int min_cluster_size = 1;
};

struct Bisection {
  bool valid = false;  // false when n < 2 (nothing to split)
  // The two sides, each sorted ascending; `a` holds the smallest node index.
  std::vector<int> a, b;
  // Exact Ncut of (a, b), in [0, 2] (not the relaxed eigenvalue).
  double ncut = 2.0;
  Fiedler fiedler;  // empty y for splits along components
};

// Splits W (see the header comment). For a connected graph the threshold on
// y is chosen by options.split_method; if the mean or sign threshold leaves a
// side empty (y numerically constant) the sweep is used instead.
Bisection spectral_bisection(const WeightMatrix& W,
                             const BisectionOptions& options = {});

// The split of y at `threshold`: in_a[i] = y[i] > threshold.
std::vector<char> split_at(const Eigen::VectorXd& y, double threshold);

// The least-Ncut split among the n-1 thresholds between sorted components of
// y, both sides >= min_size nodes; empty if there is none. O(nnz + n log n).
std::vector<char> sweep_split(const WeightMatrix& W, const Eigen::VectorXd& y,
                              int min_size);

}  // namespace hmt::area
