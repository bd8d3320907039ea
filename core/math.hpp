// Small geometric helpers on top of Eigen: vectors, unit quaternions, rotation vectors.
#pragma once

#include <Eigen/Dense>
#include <cmath>

namespace rodend {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
/// The same on a scalar S (double, or a dual number of core/dual.hpp).
template <class S>
using Vec3T = Eigen::Matrix<S, 3, 1>;
template <class S>
using Mat3T = Eigen::Matrix<S, 3, 3>;
template <class S>
using QuatT = Eigen::Quaternion<S>;
/// T in a context that template argument deduction skips (std::type_identity_t of C++20): lets
/// an argument that is an Eigen expression convert to the type deduced from the others.
template <class T>
struct NonDeduced {
  using type = T;
};
template <class T>
using nondeduced_t = typename NonDeduced<T>::type;

/// Rotation vector of a quaternion that is already unit to round-off (a product of unit
/// quaternions), angle in [0, pi]. For angles up to 2 atan(1/8) (14 degrees), the usual range of
/// a spring's twist, angle / sin(angle/2) comes from the series of atan(x)/x, x = tan(angle/2),
/// summed to round-off: no inverse trigonometric call. A template on the scalar S (double, or a
/// dual number of core/dual.hpp for exact Jacobians).
template <class S>
Eigen::Matrix<S, 3, 1> rotation_vector_of_unit(const Eigen::Quaternion<S>& q_in) {
  using std::atan2, std::sqrt;
  Eigen::Quaternion<S> q = q_in;
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // shortest rotation
  const Eigen::Matrix<S, 3, 1> v = q.vec();
  const S s2 = v.squaredNorm();  // sin^2(angle/2)
  const S w = q.w();             // cos(angle/2)
  S factor;                      // angle / sin(angle/2)
  if (s2 <= w * w * (1.0 / 64.0)) {
    // 2 atan(x)/(x w), x = s/w <= 1/8: sum_k (-x^2)^k / (2k+1), k <= 9 (x^20/21 < 1e-19)
    const S x2 = s2 / (w * w);
    S sum = 1.0 / 19.0;
    for (int k = 8; k >= 0; --k) sum = 1.0 / (2 * k + 1) - x2 * sum;
    factor = 2.0 * sum / w;
  } else {
    const S s = sqrt(s2);
    factor = 2.0 * atan2(s, w) / s;
  }
  return factor * v;
}

/// Rotation vector (unit axis times angle [rad]) of the rotation `q`, angle in [0, pi].
/// Exact and finite at zero rotation: no division by sin(angle) (thesis eq. 4.6-4.7 divide by
/// sin(Phi), which is singular at rest; model-notes §5).
inline Vec3 rotation_vector(const Quat& q_in) {
  return rotation_vector_of_unit(q_in.normalized());
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
