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
struct SpringAnchor {
  Vec3 p_W = Vec3::Zero();        ///< anchor position [m] (rest position of the body)
  Vec3 v_W = Vec3::Zero();        ///< anchor velocity [m/s]
  Quat q_ref = Quat::Identity();  ///< orientation the body is held to
  Vec3 w_ref_W = Vec3::Zero();    ///< angular velocity of that orientation [rad/s]
};

struct SpringEval {
  Vec3 force_on_body = Vec3::Zero();   ///< [N]; the anchor receives the opposite
  Vec3 moment_on_body = Vec3::Zero();  ///< [N m]; the anchor receives the opposite
  double potential = 0.0;              ///< elastic energy [J]
  double damping_power = 0.0;          ///< dissipated power [W], >= 0
  /// Power delivered by whatever moves the anchor [W] (input work of a prescribed anchor).
  double anchor_power = 0.0;
};

/// F = k (p_a - p_b) + d (v_a - v_b)                         (thesis 4.4-4.5)
/// M = -k_r r - d_r (w_b - w_ref),  r = rotation vector of q_b q_ref^-1
/// U = k |p_a - p_b|^2 / 2 + k_r |r|^2 / 2 is exact for this moment, since d|r|/dt is the
/// component of (w_b - w_ref) along r.
inline SpringEval evaluate_spring(const Spring3DParams& s, const SpringAnchor& a,
                                  const BodyKinematics& b) {
  SpringEval e;
  const Vec3 dp = a.p_W - b.p_W;
  const Vec3 dv = a.v_W - b.v_W;
  e.force_on_body = s.stiffness * dp + s.damping * dv;
  // both unit: the body's normalised orientation and the anchor's reference
  const Vec3 r = rotation_vector_of_unit(b.q_WB * a.q_ref.conjugate());
  const Vec3 dw = b.w_W - a.w_ref_W;
  e.moment_on_body = -s.rotational_stiffness * r - s.rotational_damping * dw;
  e.potential =
      0.5 * s.stiffness * dp.squaredNorm() + 0.5 * s.rotational_stiffness * r.squaredNorm();
  e.damping_power = s.damping * dv.squaredNorm() + s.rotational_damping * dw.squaredNorm();
  e.anchor_power = e.force_on_body.dot(a.v_W) + e.moment_on_body.dot(a.w_ref_W);
  return e;
}

}  // namespace rodend
