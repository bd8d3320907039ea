// Small geometric helpers on top of Eigen: vectors, unit quaternions, rotation vectors.
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace rodend {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Rotation vector (unit axis times angle [rad]) of the rotation `q`, angle in [0, pi].
/// Exact and finite at zero rotation: no division by sin(angle) (thesis eq. 4.6-4.7 divide by
/// sin(Phi), which is singular at rest; model-notes §5).
inline Vec3 rotation_vector(const Quat& q_in) {
  Quat q = q_in.normalized();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // shortest rotation
  const Vec3 v = q.vec();
  const double s = v.norm();  // sin(angle/2)
  const double w = q.w();     // cos(angle/2)
  const double angle = 2.0 * std::atan2(s, w);
  // angle / s -> 2 / w as s -> 0 (series of atan2(s, w) / s = (1/w)(1 - s^2/(3 w^2) + ...))
  const double factor = (s > 1e-7) ? angle / s : (2.0 / w) * (1.0 - s * s / (3.0 * w * w));
  return factor * v;
}

/// Quaternion of the rotation by `rv` (axis * angle), exact at zero.
inline Quat quat_from_rotation_vector(const Vec3& rv) {
  const double angle = rv.norm();
  const double half = 0.5 * angle;
  // sin(half)/angle -> 1/2 - angle^2/48 as angle -> 0
  const double k = (angle > 1e-7) ? std::sin(half) / angle : 0.5 - angle * angle / 48.0;
  return Quat(std::cos(half), k * rv.x(), k * rv.y(), k * rv.z());
}

/// 3-2-1 (yaw psi, pitch theta, roll phi) Euler angles [rad] of the body-to-inertial rotation
/// `R_WB`, returned as (phi, theta, psi). An output only: nothing is integrated in these angles,
/// so the singularity at theta = +-90 deg (thesis eq. 3.40) never enters the dynamics.
inline Vec3 euler321(const Mat3& R_WB) {
  const double psi = std::atan2(R_WB(1, 0), R_WB(0, 0));
  const double theta = std::asin(std::clamp(-R_WB(2, 0), -1.0, 1.0));
  const double phi = std::atan2(R_WB(2, 1), R_WB(2, 2));
  return Vec3(phi, theta, psi);
}

}  // namespace rodend
