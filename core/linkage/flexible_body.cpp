#include "core/linkage/flexible_body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rodend::linkage {
namespace {

/// The 90-degree rotation J = [[0, -1], [1, 0]] (d A / d phi = A J).
Eigen::Matrix2d rot90() {
  Eigen::Matrix2d j;
  j << 0.0, -1.0, 1.0, 0.0;
  return j;
}

Eigen::Matrix2d rotation(double phi) {
  Eigen::Matrix2d a;
  a << std::cos(phi), -std::sin(phi), std::sin(phi), std::cos(phi);
  return a;
}

}  // namespace

FlexibleBody::FlexibleBody(BeamModes modes, const Eigen::Vector2d& axis_start,
                           const Eigen::Vector2d& axis_end,
                           const std::vector<Eigen::Vector2d>& points, double damping_ratio)
    : modes_(std::move(modes)), n_(modes_.count()), axis_start_(axis_start) {
  if (!(damping_ratio >= 0.0)) throw std::invalid_argument("flexible body: expected zeta >= 0");
  const double length = modes_.length();
  if (std::abs((axis_end - axis_start).norm() - length) > 1e-9 * length)
    throw std::invalid_argument("flexible body: the axis is " +
                                std::to_string((axis_end - axis_start).norm()) +
                                " m long, the beam " + std::to_string(length) + " m");
  axis_ = (axis_end - axis_start) / length;
  normal_ = rot90() * axis_;
  // unit largest nodal displacement: the amplitude is that displacement [m]
  for (int i = 0; i < n_; ++i) {
    double big = 0.0;
    const Eigen::VectorXd& p = modes_.shape(i);
    for (int k = 0; k < p.size(); ++k)
      if (k % 3 != 2) big = std::max(big, std::abs(p(k)));
    if (!(big > 0.0)) throw std::invalid_argument("flexible body: a mode without displacement");
    modes_.scale(i, 1.0 / big);
  }
  integrate_invariants();
  stiffness_.resize(n_);
  damping_.resize(n_);
  for (int i = 0; i < n_; ++i) {
    const double w = modes_.frequency(i);
    stiffness_(i) = mff_(i, i) * w * w;
    damping_(i) = 2.0 * damping_ratio * mff_(i, i) * w;
  }
  for (const auto& p : points) add_point(p);
}

void FlexibleBody::add_point(const Eigen::Vector2d& p) {
  const double length = modes_.length();
  const double s = (p - axis_start_).dot(axis_), d = (p - axis_start_).dot(normal_);
  if (s < -1e-9 * length || s > length * (1.0 + 1e-9))
    throw std::invalid_argument("flexible body: a point outside the beam's span (" +
                                std::to_string(s) + " m along its axis of " +
                                std::to_string(length) + " m)");
  PointShape ps{p, Eigen::Matrix<double, 2, Eigen::Dynamic>(2, n_), Eigen::RowVectorXd(n_)};
  for (int i = 0; i < n_; ++i) {
    const ModeShapeAt m = modes_.at(i, std::clamp(s, 0.0, length));
    ps.s.col(i) = (m.axial - d * m.slope) * axis_ + m.transverse * normal_;
    ps.slope(i) = m.slope;
  }
  points_.push_back(std::move(ps));
}

void FlexibleBody::integrate_invariants() {
  static constexpr double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                  0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538};
  const Eigen::Matrix2d j = rot90();
  sbar_ = Eigen::Matrix<double, 2, Eigen::Dynamic>::Zero(2, n_);
  i1_ = i2_ = Eigen::VectorXd::Zero(n_);
  mff_ = stilde_ = Eigen::MatrixXd::Zero(n_, n_);
  const auto& nodes = modes_.nodes();
  Eigen::Matrix<double, 2, Eigen::Dynamic> s(2, n_);
  for (std::size_t e = 0; e + 1 < nodes.size(); ++e) {
    const double a = nodes[e], h = nodes[e + 1] - a;
    i00_ += modes_.rotary_inertia_per_length()[e] * h;  // the sections' own rotary inertia
    for (int k = 0; k < 4; ++k) {
      const double st = a + 0.5 * h * (1.0 + g[k]),
                   dm = 0.5 * h * w[k] * modes_.mass_per_length()[e];
      const Eigen::Vector2d u0 = axis_start_ + st * axis_;
      for (int i = 0; i < n_; ++i) {
        const ModeShapeAt m = modes_.at(i, st);
        s.col(i) = m.axial * axis_ + m.transverse * normal_;
      }
      mass_ += dm;
      s0_ += dm * u0;
      sbar_ += dm * s;
      i00_ += dm * u0.squaredNorm();
      i1_ += dm * s.transpose() * u0;
      i2_ += dm * s.transpose() * (j * u0);
      mff_ += dm * s.transpose() * s;
      stilde_ += dm * s.transpose() * j * s;
    }
  }
}

Eigen::MatrixXd FlexibleBody::mass_matrix(ConstVectorRef q) const {
  const auto eta = q.tail(n_);
  const Eigen::Matrix2d a = rotation(q(2)), j = rot90();
  const Eigen::Vector2d sq = s0_ + sbar_ * eta;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(3 + n_, 3 + n_);
  m.topLeftCorner<2, 2>() = mass_ * Eigen::Matrix2d::Identity();
  m.block<2, 1>(0, 2) = a * j * sq;
  m.block(0, 3, 2, n_) = a * sbar_;
  m(2, 2) = i00_ + 2.0 * i1_.dot(eta) + eta.dot(mff_ * eta);
  m.block(2, 3, 1, n_) = i2_.transpose() - eta.transpose() * stilde_;
  m.bottomRightCorner(n_, n_) = mff_;
  // the lower triangle mirrors the upper
  m.triangularView<Eigen::StrictlyLower>() = m.transpose();
  return m;
}

Eigen::VectorXd FlexibleBody::internal_forces(ConstVectorRef q, ConstVectorRef qdot,
                                              const Eigen::Vector2d& gravity) const {
  const auto eta = q.tail(n_);
  const auto etad = qdot.tail(n_);
  const double w = qdot(2);
  const Eigen::Matrix2d a = rotation(q(2)), j = rot90();
  const Eigen::Vector2d sq = s0_ + sbar_ * eta;
  const Eigen::VectorXd i1q = i1_ + mff_ * eta;
  Eigen::VectorXd f(3 + n_);
  // quadratic velocity vector
  f.head<2>() = a * (w * w * sq - 2.0 * w * j * (sbar_ * etad));
  f(2) = -2.0 * w * i1q.dot(etad);
  f.tail(n_) = w * w * i1q - 2.0 * w * (stilde_ * etad);
  // elastic and modal damping forces
  f.tail(n_) -= stiffness_.cwiseProduct(eta) + damping_.cwiseProduct(etad);
  // gravity: int rho (dr/dq)^T g
  f.head<2>() += mass_ * gravity;
  f(2) += (a * j * sq).dot(gravity);
  f.tail(n_) += (a * sbar_).transpose() * gravity;
  return f;
}

PointKinematics FlexibleBody::point(int index, ConstVectorRef q, ConstVectorRef qdot) const {
  const PointShape& p = points_.at(static_cast<std::size_t>(index));
  const auto eta = q.tail(n_);
  const auto etad = qdot.tail(n_);
  const double w = qdot(2);
  const Eigen::Matrix2d a = rotation(q(2)), j = rot90();
  const Eigen::Vector2d u = p.u0 + p.s * eta, ud = p.s * etad;
  PointKinematics k;
  k.position = q.head<2>() + a * u;
  k.velocity = qdot.head<2>() + a * (w * (j * u) + ud);
  k.jacobian.resize(2, 3 + n_);
  k.jacobian.leftCols<2>().setIdentity();
  k.jacobian.col(2) = a * j * u;
  k.jacobian.rightCols(n_) = a * p.s;
  k.jacobian_dot_qdot = a * (2.0 * w * (j * ud) - w * w * u);
  k.angle = q(2) + p.slope.dot(eta);
  k.angular_velocity = w + p.slope.dot(etad);
  k.angle_jacobian = Eigen::RowVectorXd::Zero(3 + n_);
  k.angle_jacobian(2) = 1.0;
  k.angle_jacobian.tail(n_) = p.slope;
  k.angle_jacobian_dot_qdot = 0.0;
  return k;
}

double FlexibleBody::kinetic_energy(ConstVectorRef q, ConstVectorRef qdot) const {
  return 0.5 * qdot.dot(mass_matrix(q) * qdot);
}

double FlexibleBody::potential_energy(ConstVectorRef q, const Eigen::Vector2d& gravity) const {
  const auto eta = q.tail(n_);
  const Eigen::Vector2d first_moment = mass_ * q.head<2>() + rotation(q(2)) * (s0_ + sbar_ * eta);
  return 0.5 * eta.dot(stiffness_.cwiseProduct(eta)) - gravity.dot(first_moment);
}

double FlexibleBody::dissipated_power(ConstVectorRef /*q*/, ConstVectorRef qdot) const {
  const auto etad = qdot.tail(n_);
  return etad.dot(damping_.cwiseProduct(etad));
}

}  // namespace rodend::linkage
