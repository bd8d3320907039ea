// A 6-DOF rigid body: translation in the inertial frame W, rotation by a unit quaternion q_WB,
// angular velocity in the body frame B (thesis §3.2, eq. 3.27-3.35).
#pragma once

#include "core/math.hpp"

namespace rodend {

/// Immutable parameters of a rigid body.
struct RigidBodyParams {
  double mass = 1.0;            ///< [kg]
  Vec3 inertia = Vec3::Ones();  ///< principal moments of inertia about the mass centre [kg m^2]
};

/// Layout of one body's 13 states inside the scene state vector, starting at `offset`:
/// p_W (3) [m], v_W (3) [m/s], q_WB (4: w, x, y, z) [-], w_B (3) [rad/s].
struct BodyStateLayout {
  static constexpr int size = 13;
  static constexpr int p = 0, v = 3, q = 6, w = 10;
};

/// Read-only view of a body's state with the quaternion normalised (used everywhere a rotation
/// is needed, so a small drift of |q| never distorts the dynamics). On a scalar S (double, or a
/// dual number of core/dual.hpp); BodyKinematics is the double one.
template <class S>
struct BodyKinematicsT {
  Vec3T<S> p_W;   ///< position of the mass centre [m]
  Vec3T<S> v_W;   ///< velocity of the mass centre [m/s]
  QuatT<S> q_WB;  ///< orientation, normalised
  Mat3T<S> R_WB;  ///< rotation matrix body -> inertial
  Vec3T<S> w_B;   ///< angular velocity in the body frame [rad/s]
  Vec3T<S> w_W;   ///< angular velocity in the inertial frame [rad/s]

  static BodyKinematicsT from_state(const S* x) {
    BodyKinematicsT k;
    k.p_W = Vec3T<S>(x[0], x[1], x[2]);
    k.v_W = Vec3T<S>(x[3], x[4], x[5]);
    k.q_WB = QuatT<S>(x[6], x[7], x[8], x[9]).normalized();
    k.R_WB = k.q_WB.toRotationMatrix();
    k.w_B = Vec3T<S>(x[10], x[11], x[12]);
    k.w_W = k.R_WB * k.w_B;
    return k;
  }
  /// A body held fixed at `p` with identity orientation (ground).
  static BodyKinematicsT fixed(const Vec3& p) {
    BodyKinematicsT k;
    k.p_W = p.template cast<S>();
    k.v_W.setZero();
    k.q_WB.setIdentity();
    k.R_WB.setIdentity();
    k.w_B.setZero();
    k.w_W.setZero();
    return k;
  }
};
using BodyKinematics = BodyKinematicsT<double>;

/// Writes the initial state of a body at rest at `p_W` with identity orientation.
inline void body_initial_state(double* x, const Vec3& p_W, const Vec3& v_W = Vec3::Zero(),
                               const Quat& q_WB = Quat::Identity(),
                               const Vec3& w_B = Vec3::Zero()) {
  for (int i = 0; i < 3; ++i) {
    x[i] = p_W[i];
    x[3 + i] = v_W[i];
    x[10 + i] = w_B[i];
  }
  x[6] = q_WB.w();
  x[7] = q_WB.x();
  x[8] = q_WB.y();
  x[9] = q_WB.z();
}

/// Time derivative of a body's 13 states under the total force `F_W` [N] (inertial frame) and
/// the total moment about the mass centre `M_W` [N m] (inertial frame).
///   p' = v;  v' = F/m                                   (Newton, thesis 3.27 in frame W)
///   q' = 1/2 q (x) (0, w_B)                              (replaces thesis 3.36-3.40)
///   I w_B' + w_B x (I w_B) = M_B                         (Euler, thesis 3.31-3.35 with the
///                                                         missing dot of 3.33 restored)
template <class S>
void body_derivatives(const RigidBodyParams& body, const BodyKinematicsT<S>& k,
                      const nondeduced_t<Vec3T<S>>& F_W, const nondeduced_t<Vec3T<S>>& M_W,
                      const S* x, S* dxdt) {
  const Vec3T<S> a_W = F_W / body.mass;
  const Vec3T<S> M_B = k.R_WB.transpose() * M_W;
  const Vec3& I = body.inertia;
  const Vec3T<S>& w = k.w_B;
  const Vec3T<S> Iw = I.cwiseProduct(w);
  const Vec3T<S> dw = (M_B - w.cross(Iw)).cwiseQuotient(I);
  // quaternion kinematics on the stored (not normalised) quaternion keeps the ODE smooth
  const QuatT<S> q(x[6], x[7], x[8], x[9]);
  const QuatT<S> dq = q * QuatT<S>(S(0.0), w.x(), w.y(), w.z());
  for (int i = 0; i < 3; ++i) {
    dxdt[i] = k.v_W[i];
    dxdt[3 + i] = a_W[i];
    dxdt[10 + i] = dw[i];
  }
  dxdt[6] = 0.5 * dq.w();
  dxdt[7] = 0.5 * dq.x();
  dxdt[8] = 0.5 * dq.y();
  dxdt[9] = 0.5 * dq.z();
}

/// Translational plus rotational kinetic energy [J].
inline double kinetic_energy(const RigidBodyParams& body, const BodyKinematics& k) {
  return 0.5 * body.mass * k.v_W.squaredNorm() + 0.5 * k.w_B.dot(body.inertia.cwiseProduct(k.w_B));
}

/// Angular momentum about the mass centre, in the inertial frame [kg m^2/s].
inline Vec3 angular_momentum_W(const RigidBodyParams& body, const BodyKinematics& k) {
  return k.R_WB * body.inertia.cwiseProduct(k.w_B);
}

}  // namespace rodend
