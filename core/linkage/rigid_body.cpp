// The rigid planar body: with R(phi) the rotation of the body frame and p a body-frame position,
//   r_p = r + R p,  v_p = r' + phi' R' p,  R' p = perp(R p) = (-(Rp)_y, (Rp)_x),
//   d r_p / dq = [I | perp(R p)],  (dJ/dt) q' = -phi'^2 R p.
// With c the mass centre, Newton-Euler projected on q (M q'' = Q):
//   M = [m I, m perp(Rc); m perp(Rc)^T, I_c + m |c|^2],  Q = J_c^T m (g + phi'^2 R c).
#include "core/linkage/rigid_body.hpp"

#include <cmath>
#include <utility>

namespace rodend::linkage {
namespace {

Eigen::Vector2d rotate(double phi, const Eigen::Vector2d& p) {
  const double c = std::cos(phi), s = std::sin(phi);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}
Eigen::Vector2d perp(const Eigen::Vector2d& v) {
  return {-v.y(), v.x()};
}

}  // namespace

RigidBody::RigidBody(double mass, double inertia, const Eigen::Vector2d& centre_of_mass,
                     std::vector<Eigen::Vector2d> points)
    : mass_(mass), inertia_(inertia), com_(centre_of_mass), points_(std::move(points)) {}

PointKinematics RigidBody::at(const Eigen::Vector2d& local, ConstVectorRef q,
                              ConstVectorRef qdot) const {
  const Eigen::Vector2d Rp = rotate(q[2], local), dRp = perp(Rp);
  PointKinematics k;
  k.position = Eigen::Vector2d(q[0], q[1]) + Rp;
  k.velocity = Eigen::Vector2d(qdot[0], qdot[1]) + qdot[2] * dRp;
  k.jacobian.resize(2, 3);
  k.jacobian << 1.0, 0.0, dRp.x(), 0.0, 1.0, dRp.y();
  k.jacobian_dot_qdot = -qdot[2] * qdot[2] * Rp;
  k.angle = q[2];
  k.angular_velocity = qdot[2];
  k.angle_jacobian = Eigen::RowVector3d(0.0, 0.0, 1.0);
  k.angle_jacobian_dot_qdot = 0.0;
  return k;
}

PointKinematics RigidBody::point(int index, ConstVectorRef q, ConstVectorRef qdot) const {
  return at(points_[static_cast<std::size_t>(index)], q, qdot);
}

Eigen::MatrixXd RigidBody::mass_matrix(ConstVectorRef q) const {
  const Eigen::Vector2d a = perp(rotate(q[2], com_));
  Eigen::MatrixXd M(3, 3);
  M << mass_, 0.0, mass_ * a.x(), 0.0, mass_, mass_ * a.y(), mass_ * a.x(), mass_ * a.y(),
      inertia_ + mass_ * com_.squaredNorm();
  return M;
}

Eigen::VectorXd RigidBody::internal_forces(ConstVectorRef q, ConstVectorRef qdot,
                                           const Eigen::Vector2d& gravity) const {
  const PointKinematics c = at(com_, q, qdot);
  return c.jacobian.transpose() * (mass_ * (gravity - c.jacobian_dot_qdot));
}

double RigidBody::kinetic_energy(ConstVectorRef q, ConstVectorRef qdot) const {
  const PointKinematics c = at(com_, q, qdot);
  return 0.5 * mass_ * c.velocity.squaredNorm() + 0.5 * inertia_ * qdot[2] * qdot[2];
}

double RigidBody::potential_energy(ConstVectorRef q, const Eigen::Vector2d& gravity) const {
  const Eigen::Vector2d r = Eigen::Vector2d(q[0], q[1]) + rotate(q[2], com_);
  return -mass_ * gravity.dot(r);
}

}  // namespace rodend::linkage
