#include "hmt/experiments/ekf_slam.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

namespace hmt::experiments {

EkfSlam2D::EkfSlam2D(const EkfNoise& noise)
    : noise_(noise), x_(Eigen::VectorXd::Zero(3)), P_(Eigen::MatrixXd::Zero(3, 3)) {}

Pose2D EkfSlam2D::pose() const { return Pose2D(x_(0), x_(1), x_(2)); }

int EkfSlam2D::index_of(int id) const {
  const auto it = index_.find(id);
  return it == index_.end() ? -1 : it->second;
}

void EkfSlam2D::predict(const Pose2D& u, const Eigen::Matrix3d& Q) {
  const double th = x_(2), c = std::cos(th), s = std::sin(th);
  Eigen::Matrix3d Fx = Eigen::Matrix3d::Identity();
  Fx(0, 2) = -s * u.x - c * u.y;
  Fx(1, 2) = c * u.x - s * u.y;
  Eigen::Matrix3d Fu;
  Fu << c, -s, 0, s, c, 0, 0, 0, 1;

  x_(0) += c * u.x - s * u.y;
  x_(1) += s * u.x + c * u.y;
  x_(2) = wrap_angle(th + u.theta);

  const Eigen::Index n = x_.size();
  const Eigen::Matrix3d Prr = P_.topLeftCorner<3, 3>();
  P_.topLeftCorner<3, 3>() =
      Fx * Prr * Fx.transpose() + Fu * Q * Fu.transpose();
  if (n > 3) {
    const Eigen::MatrixXd Prl = Fx * P_.topRightCorner(3, n - 3);
    P_.topRightCorner(3, n - 3) = Prl;
    P_.bottomLeftCorner(n - 3, 3) = Prl.transpose();
  }
}

void EkfSlam2D::update(const std::vector<RangeBearing>& z) {
  std::vector<const RangeBearing*> known, fresh;
  for (const RangeBearing& m : z) {
    if (m.id < 0) throw std::invalid_argument("EkfSlam2D::update: negative id");
    (index_of(m.id) >= 0 ? known : fresh).push_back(&m);
  }

  if (!known.empty()) {
    const Eigen::Index n = x_.size();
    const int m = static_cast<int>(known.size());
    // Innovation nu, Jacobian H (2m x n, sparse: robot + one landmark each).
    Eigen::VectorXd nu(2 * m);
    Eigen::MatrixXd PHt = Eigen::MatrixXd::Zero(n, 2 * m);  // P H^T
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * m, 2 * m);
    std::vector<Eigen::Matrix<double, 2, 3>> Hr(m);
    std::vector<Eigen::Matrix2d> Hl(m);
    std::vector<int> col(m);
    for (int i = 0; i < m; ++i) {
      const int k = index_of(known[i]->id);
      col[i] = 3 + 2 * k;
      const double dx = x_(col[i]) - x_(0), dy = x_(col[i] + 1) - x_(1);
      const double q = dx * dx + dy * dy, r = std::sqrt(q);
      nu(2 * i) = known[i]->range - r;
      nu(2 * i + 1) = wrap_angle(known[i]->bearing - (std::atan2(dy, dx) - x_(2)));
      Hr[i] << -dx / r, -dy / r, 0, dy / q, -dx / q, -1;
      Hl[i] << dx / r, dy / r, -dy / q, dx / q;
      PHt.middleCols<2>(2 * i) = P_.leftCols<3>() * Hr[i].transpose() +
                                 P_.middleCols<2>(col[i]) * Hl[i].transpose();
    }
    // S = H P H^T + R, from the rows of P H^T that H selects.
    for (int i = 0; i < m; ++i) {
      S.middleRows<2>(2 * i) = Hr[i] * PHt.topRows<3>() +
                               Hl[i] * PHt.middleRows<2>(col[i]);
      S(2 * i, 2 * i) += noise_.range_std * noise_.range_std;
      S(2 * i + 1, 2 * i + 1) += noise_.bearing_std * noise_.bearing_std;
    }
    S = 0.5 * (S + S.transpose()).eval();
    const Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success)
      throw std::runtime_error("EkfSlam2D::update: innovation covariance not positive definite");
    // K = P H^T S^-1; P <- P - K S K^T = P - PHt S^-1 PHt^T.
    const Eigen::MatrixXd SinvHP = llt.solve(PHt.transpose());  // 2m x n
    x_ += SinvHP.transpose() * nu;
    x_(2) = wrap_angle(x_(2));
    P_.noalias() -= PHt * SinvHP;
    P_ = 0.5 * (P_ + P_.transpose()).eval();
  }
  for (const RangeBearing* m : fresh) add_landmark(*m);
}

void EkfSlam2D::add_landmark(const RangeBearing& m) {
  if (index_of(m.id) >= 0) return;  // the same id twice in one observation
  const double a = x_(2) + m.bearing, c = std::cos(a), s = std::sin(a);
  const double r = m.range;
  Eigen::Matrix<double, 2, 3> Gr;
  Gr << 1, 0, -r * s, 0, 1, r * c;
  Eigen::Matrix2d Gz;
  Gz << c, -r * s, s, r * c;
  const Eigen::Vector2d var(noise_.range_std * noise_.range_std,
                            noise_.bearing_std * noise_.bearing_std);

  const Eigen::Index n = x_.size();
  x_.conservativeResize(n + 2);
  x_(n) = x_(0) + r * c;
  x_(n + 1) = x_(1) + r * s;
  const Eigen::MatrixXd Plx = Gr * P_.topRows<3>();  // 2 x n
  P_.conservativeResize(n + 2, n + 2);
  P_.block(n, 0, 2, n) = Plx;
  P_.block(0, n, n, 2) = Plx.transpose();
  P_.block<2, 2>(n, n) = Gr * Plx.leftCols<3>().transpose() +
                         Gz * var.asDiagonal() * Gz.transpose();
  index_[m.id] = static_cast<int>(ids_.size());
  ids_.push_back(m.id);
}

EkfSlam2D run_ekf(const LandmarkSim& sim, const LandmarkSimOptions& o,
                  std::vector<PoseEstimate>* poses) {
  EkfSlam2D ekf({o.range_std, o.bearing_std});
  const Eigen::Vector3d q(o.odo_xy_std * o.odo_xy_std, o.odo_xy_std * o.odo_xy_std,
                          o.odo_phi_std * o.odo_phi_std);
  const Eigen::Matrix3d Q = q.asDiagonal();
  if (poses) poses->clear();
  for (size_t t = 0; t < sim.steps.size(); ++t) {
    if (t > 0) ekf.predict(sim.steps[t].odometry, Q);
    ekf.update(sim.steps[t].z);
    if (poses) poses->push_back({ekf.pose(), ekf.pose_cov()});
  }
  return ekf;
}

}  // namespace hmt::experiments
