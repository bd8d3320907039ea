// The friction force of a stuck contact in friction.mode switch (Leine's switch model; Karnopp's
// stick): the tangential force f that holds the slip velocity of the ball's contact point
// relative to the socket's at zero, computed from every other force and moment on the two
// bodies, up to the static limit mu F_n. On a scalar S (double, or a dual number of
// core/dual.hpp for the exact Jacobians).
//
// The slip velocity (contact_eval.hpp, thesis 3.12-3.13), r_b = R_b n and r_s = R_s n:
//   v_rel = (v_b + w_b x r_b) - (v_s + w_s x r_s),   v_t = P v_rel,   P = 1 - n n^T.
// Its rate, with n' = P (v_b - v_s) / |e| (n = e / |e|, e the socket-to-ball offset):
//   v_t' = P v_rel' - n' (n . v_rel)  (the tangential part of P' v_rel),
//   v_rel' = a_b + alpha_b x r_b + w_b x R_b n' - (a_s + alpha_s x r_s + w_s x R_s n').
// f acts on the ball at its contact point and -f on the socket at its own (the moments r x f of
// contact_eval.hpp), so the accelerations are affine in f:
//   a_b = a_b0 + f / m_b,       alpha_b = alpha_b0 + J_b^-1 (r_b x f),
//   a_s = a_s0 - f / m_s,       alpha_s = alpha_s0 - J_s^-1 (r_s x f),
// J^-1 = R diag(1/I) R^T in the world frame, a_0 and alpha_0 from the other forces and
// moments and the gyroscopic term (rigid_body.hpp, body_derivatives). So v_t' = v_t0' + P A f
//   A f = (1/m_b + 1/m_s) f + (J_b^-1 (r_b x f)) x r_b + (J_s^-1 (r_s x f)) x r_s,
// A the contact's inverse mass (symmetric, positive definite in the tangent plane). Stuck:
//   P A f = -v_t0' - v_t / tau,  f in the tangent plane (two equations, two unknowns),
// with the drift term -v_t / tau: the slip a contact sticks with (below the switch speed v_st)
// and round-off decay with time constant tau instead of persisting.
#pragma once

#include <cmath>

#include "core/contact.hpp"
#include "core/dual.hpp"
#include "core/rigid_body.hpp"

namespace rodend {

/// The time constant tau with which a stuck contact's residual slip decays [s]. Assumed: 1 ms,
/// two decades above the rod-end's contact modes (20-70 us) and below its stuck stretches
/// (5 ms median): a contact that sticks at v_st = 1 mm/s slides a further 1 um, and the decay
/// is a stable mode of -1e3 s^-1 that an implicit method steps over.
inline constexpr double kStickDriftTime = 1e-3;

/// One body of a stuck contact, as its stick force sees it.
template <class S>
struct StickBody {
  const BodyKinematicsT<S>* kinematics = nullptr;
  double inv_mass = 0.0;               ///< 1/m [1/kg]; 0: a fixed body
  Vec3 inertia = Vec3::Ones();         ///< principal moments about the mass centre [kg m^2]
  bool turns = true;                   ///< false: the body does not rotate (a block, a fixed body)
  Vec3T<S> force = Vec3T<S>::Zero();   ///< every other force on it, world frame [N]
  Vec3T<S> moment = Vec3T<S>::Zero();  ///< every other moment about its mass centre [N m]
  double radius = 0.0;                 ///< its contact point lies at radius n from its centre [m]
};

namespace stick_detail {

/// The world angular acceleration of a body under its other moment (Euler's equation).
template <class S>
Vec3T<S> free_angular_acceleration(const StickBody<S>& b) {
  if (!b.turns || b.inv_mass == 0.0) return Vec3T<S>::Zero();
  const BodyKinematicsT<S>& k = *b.kinematics;
  const Vec3T<S> M_B = k.R_WB.transpose() * b.moment;
  const Vec3T<S> Iw = b.inertia.cwiseProduct(k.w_B);
  return k.R_WB * (M_B - k.w_B.cross(Iw)).cwiseQuotient(b.inertia.template cast<S>());
}

/// The acceleration of a body's contact point per unit force g at it (inverse mass; the
/// force's moment r x g turns the body).
template <class S>
Vec3T<S> point_compliance(const StickBody<S>& b, const Vec3T<S>& r, const Vec3T<S>& g) {
  Vec3T<S> a = b.inv_mass * g;
  if (!b.turns || b.inv_mass == 0.0) return a;
  const BodyKinematicsT<S>& k = *b.kinematics;
  const Vec3T<S> m_B = k.R_WB.transpose() * r.cross(g);
  const Vec3T<S> alpha = k.R_WB * m_B.cwiseQuotient(b.inertia.template cast<S>());
  return a + alpha.cross(r);
}

/// A unit vector normal to n (n a unit vector), from the world axis least aligned with it.
template <class S>
Vec3T<S> tangent_to(const Vec3T<S>& n) {
  using std::abs;
  const double x = abs(value_of(n.x())), y = abs(value_of(n.y())), z = abs(value_of(n.z()));
  const Vec3 axis = x <= y && x <= z ? Vec3::UnitX() : (y <= z ? Vec3::UnitY() : Vec3::UnitZ());
  const Vec3T<S> t = n.cross(axis.template cast<S>());
  return t / t.norm();
}

}  // namespace stick_detail

/// The friction force on the ball that holds the contact's slip velocity at zero (the
/// derivation above), unbounded; `c` the contact evaluated without friction (its normal, the
/// eccentricity), `ball` and `socket` the two bodies with every other force on them.
template <class S>
Vec3T<S> stick_force(const ContactEvalT<S>& c, const StickBody<S>& ball,
                     const StickBody<S>& socket) {
  using namespace stick_detail;
  const Vec3T<S>& n = c.normal;
  const BodyKinematicsT<S>&kb = *ball.kinematics, &ks = *socket.kinematics;
  const Vec3T<S> rb = ball.radius * n, rs = socket.radius * n;
  auto tangential = [&](const Vec3T<S>& v) -> Vec3T<S> { return v - v.dot(n) * n; };
  const Vec3T<S> v_rel = (kb.v_W + kb.w_W.cross(rb)) - (ks.v_W + ks.w_W.cross(rs));
  const Vec3T<S> v_t = tangential(v_rel);
  const Vec3T<S> n_dot = tangential(kb.v_W - ks.v_W) / c.eccentricity;
  // the rate of v_t without friction
  const Vec3T<S> a_b = ball.inv_mass * ball.force + free_angular_acceleration(ball).cross(rb) +
                       kb.w_W.cross(ball.radius * n_dot);
  const Vec3T<S> a_s = socket.inv_mass * socket.force +
                       free_angular_acceleration(socket).cross(rs) +
                       ks.w_W.cross(socket.radius * n_dot);
  const Vec3T<S> rhs = -(tangential(a_b - a_s) - n_dot * v_rel.dot(n)) - v_t / kStickDriftTime;
  // P A f = rhs in the tangent basis (t1, t2): a symmetric 2 x 2 system
  const Vec3T<S> t1 = tangent_to(n), t2 = n.cross(t1);
  auto A = [&](const Vec3T<S>& g) -> Vec3T<S> {
    return point_compliance(ball, rb, g) + point_compliance(socket, rs, g);
  };
  const Vec3T<S> A1 = A(t1), A2 = A(t2);
  const S k11 = t1.dot(A1), k12 = 0.5 * (t1.dot(A2) + t2.dot(A1)), k22 = t2.dot(A2);
  const S b1 = t1.dot(rhs), b2 = t2.dot(rhs);
  const S det = k11 * k22 - k12 * k12;
  return ((k22 * b1 - k12 * b2) / det) * t1 + ((k11 * b2 - k12 * b1) / det) * t2;
}

/// Applies the stuck force `required` (stick_force) to the contact `c` evaluated without
/// friction: bounded by the static limit mu F_n (beyond it, the limit along `required`: the
/// contact starts to slide, and the driver switches it to slipping once it passes the switch
/// speed), its moments r x f on each sphere, its power -f . v_t and its demand |f| / (mu F_n).
template <class S>
void apply_stick(const ClearanceContactModel& m, ContactEvalT<S>& c, const StickBody<S>& ball,
                 const StickBody<S>& socket, const Vec3T<S>& required) {
  using std::sqrt;
  const S limit = m.static_limit * c.normal_force;
  const S size = sqrt(required.squaredNorm());
  c.stick_demand = value_of(limit) > 0.0 ? value_of(size) / value_of(limit) : 0.0;
  const Vec3T<S> f = c.stick_demand > 1.0 ? Vec3T<S>((limit / size) * required) : required;
  const BodyKinematicsT<S>&kb = *ball.kinematics, &ks = *socket.kinematics;
  const Vec3T<S> rb = ball.radius * c.normal, rs = socket.radius * c.normal;
  const Vec3T<S> v_rel = (kb.v_W + kb.w_W.cross(rb)) - (ks.v_W + ks.w_W.cross(rs));
  c.friction_on_ball = f;
  c.moment_on_ball += rb.cross(f);
  c.moment_on_socket += rs.cross(-f);
  c.friction_power = -f.dot(v_rel - v_rel.dot(c.normal) * c.normal);
}

}  // namespace rodend
