// Three-dimensional spring: linear stiffness and damping plus rotational stiffness and damping
// (thesis §4, eq. 4.4-4.7; model-notes §5). The rotational part holds a body to the orientation
// of the link it is mounted on, through a rotation vector that is exact and finite at zero.
#pragma once

#include "core/math.hpp"
#include "core/rigid_body.hpp"

namespace rodend {

struct Spring3DParams {
  double stiffness = 0.0;             ///< linear stiffness k [N/m]
  double damping = 0.0;               ///< linear damping d [N s/m]
  double rotational_stiffness = 0.0;  ///< [N m/rad]
  double rotational_damping = 0.0;    ///< [N m s/rad]
};

/// The far end of a spring: where it is, how it moves, and the orientation it holds the body to.
/// On a scalar S (double, or a dual number of core/dual.hpp); SpringAnchor is the double one.
template <class S>
struct SpringAnchorT {
  Vec3T<S> p_W = Vec3T<S>::Zero();        ///< anchor position [m] (rest position of the body)
  Vec3T<S> v_W = Vec3T<S>::Zero();        ///< anchor velocity [m/s]
  QuatT<S> q_ref = QuatT<S>::Identity();  ///< orientation the body is held to
  Vec3T<S> w_ref_W = Vec3T<S>::Zero();    ///< angular velocity of that orientation [rad/s]
};
using SpringAnchor = SpringAnchorT<double>;

template <class S>
struct SpringEvalT {
  Vec3T<S> force_on_body = Vec3T<S>::Zero();   ///< [N]; the anchor receives the opposite
  Vec3T<S> moment_on_body = Vec3T<S>::Zero();  ///< [N m]; the anchor receives the opposite
  S damping_power = 0.0;                       ///< dissipated power [W], >= 0
  /// Power delivered by whatever moves the anchor [W] (input work of a prescribed anchor).
  S anchor_power = 0.0;
};
using SpringEval = SpringEvalT<double>;

/// F = k (p_a - p_b) + d (v_a - v_b)                         (thesis 4.4-4.5)
/// M = -k_r r - d_r (w_b - w_ref),  r = rotation vector of q_b q_ref^-1
/// and the powers; the elastic energy is spring_potential's (the right-hand side needs only
/// forces and powers).
template <class S>
SpringEvalT<S> evaluate_spring(const Spring3DParams& s, const SpringAnchorT<S>& a,
                               const BodyKinematicsT<S>& b) {
  SpringEvalT<S> e;
  const Vec3T<S> dp = a.p_W - b.p_W;
  const Vec3T<S> dv = a.v_W - b.v_W;
  e.force_on_body = s.stiffness * dp + s.damping * dv;
  // both unit: the body's normalised orientation and the anchor's reference
  const Vec3T<S> r = rotation_vector_of_unit(QuatT<S>(b.q_WB * a.q_ref.conjugate()));
  const Vec3T<S> dw = b.w_W - a.w_ref_W;
  e.moment_on_body = -s.rotational_stiffness * r - s.rotational_damping * dw;
  e.damping_power = s.damping * dv.squaredNorm() + s.rotational_damping * dw.squaredNorm();
  e.anchor_power = e.force_on_body.dot(a.v_W) + e.moment_on_body.dot(a.w_ref_W);
  return e;
}

/// The elastic energy of evaluate_spring's spring [J]: U = k |p_a - p_b|^2 / 2 + k_r |r|^2 / 2,
/// exact for its moment, since d|r|/dt is the component of (w_b - w_ref) along r.
template <class S>
S spring_potential(const Spring3DParams& s, const SpringAnchorT<S>& a,
                   const BodyKinematicsT<S>& b) {
  const Vec3T<S> dp = a.p_W - b.p_W;
  const Vec3T<S> r = rotation_vector_of_unit(QuatT<S>(b.q_WB * a.q_ref.conjugate()));
  return 0.5 * s.stiffness * dp.squaredNorm() + 0.5 * s.rotational_stiffness * r.squaredNorm();
}

}  // namespace rodend
