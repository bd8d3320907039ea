// The clearance contact's force pipeline (contact.hpp) as a template on the scalar S: double
// (evaluate_contact, contact_gap in contact_eval.cpp) or a dual number of core/dual.hpp, whose
// derivatives make a scene's exact Jacobian. One text for both, so they never disagree.
#pragma once

#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "core/contact.hpp"
#include "core/dual.hpp"

namespace rodend::contact_detail {

/// delta^n; the Hertz exponent 1.5 of both geometries as delta sqrt(delta) (no pow call).
template <class S>
S power_law(const S& delta, double n) {
  using std::pow, std::sqrt;
  return n == 1.5 ? S(delta * sqrt(delta)) : S(pow(delta, n));
}

template <class S>
S elastic_force(const ClearanceContactModel& m, const S& delta) {
  using std::sqrt;
  switch (m.geometry) {
    case ContactGeometry::sphere:
      return m.stiffness * power_law(delta, m.exponent);
    case ContactGeometry::cylinder:
      return m.stiffness * power_law(delta, m.exponent) / sqrt(2.0 * (m.clearance + delta));
  }
  return S(0.0);
}

/// mu(v) of the law, and for a dual its derivative through FrictionLaw::slope.
inline double friction_coefficient(const FrictionLaw& f, double v) {
  return f.coefficient(v);
}
template <int N>
Dual<N> friction_coefficient(const FrictionLaw& f, const Dual<N>& v) {
  return Dual<N>::chain(v, f.coefficient(v.v), f.slope(v.v));
}

/// The penetration delta = |e| - c(n) of a contact and its gradient. Without worn surfaces
/// c(n) = c and the gradient is the contact normal. With them, c(n) = c + h_b(R_b^T n) +
/// h_s(R_s^T n), and
///   d delta / d p_ball        = n - (g_b + g_s) / |e|      (= - d delta / d p_socket)
///   d delta / d theta_ball    = n x g_b                     (small rotation of the ball, world)
///   d delta / d theta_socket  = n x g_s
/// with g the map gradients with respect to the direction (world frame): the normal force
/// F_n acts on each body along minus these, so the contact stays conservative (the work of
/// F_el is minus the change of its potential) on a worn, non-spherical surface. Worn surfaces
/// are read in double only (a scene on them keeps the default Jacobian).
template <class S>
struct Penetration {
  Vec3T<S> normal = Vec3T<S>::UnitX();
  S eccentricity = 0.0;
  S clearance = 0.0;  ///< local clearance c(n) [m]
  Vec3T<S> along_ball = Vec3T<S>::UnitX();
  Vec3T<S> turn_ball = Vec3T<S>::Zero(), turn_socket = Vec3T<S>::Zero();
  bool centred = false;  ///< concentric: no direction
  S value() const { return eccentricity - clearance; }
  S rate(const BodyKinematicsT<S>& ball, const BodyKinematicsT<S>& socket) const {
    return along_ball.dot(ball.v_W - socket.v_W) + turn_ball.dot(ball.w_W) +
           turn_socket.dot(socket.w_W);
  }
};

template <class S>
Penetration<S> penetration(const ClearanceContactModel& m, const BodyKinematicsT<S>& ball,
                           const BodyKinematicsT<S>& socket) {
  Penetration<S> p;
  const Vec3T<S> d = ball.p_W - socket.p_W;  // socket centre -> ball centre
  p.eccentricity = d.norm();
  p.clearance = m.clearance;
  if (p.eccentricity < 1e-300) {
    p.centred = true;
    return p;
  }
  p.normal = d / p.eccentricity;
  p.along_ball = p.normal;
  if (m.worn) {
    if constexpr (std::is_same_v<S, double>) {
      Vec3 gb, gs;
      p.clearance += m.worn->extra_clearance(p.normal, ball.R_WB, socket.R_WB, &gb, &gs);
      p.along_ball -= (gb + gs) / p.eccentricity;
      p.turn_ball = p.normal.cross(gb);
      p.turn_socket = p.normal.cross(gs);
    } else {
      throw std::logic_error("worn surfaces have no exact Jacobian");
    }
  }
  return p;
}

/// Normal force (thesis 3.3, 3.6-3.8, the eq. 3.14 cap), its energy terms and the slip velocity
/// of the ball's contact point; `c` holds the penetration and its rate, > 0. Inlined in both
/// instantiations of evaluate (an outlined call costs the right-hand side ~25 instructions).
template <class S>
[[gnu::always_inline]] inline Vec3T<S> normal_force(const ClearanceContactModel& m,
                                                    const Penetration<S>& p,
                                                    const ContactLatch& latch, ContactEvalT<S>& c) {
  using std::abs;
  c.elastic_force = elastic_force(m, c.penetration);
  const S approach = latch.in_contact ? S(latch.impact_speed) : S(abs(c.penetration_rate));
  const S impact_speed = max_of(approach, m.min_impact_speed);
  const S ratio = m.hysteresis * c.penetration_rate / impact_speed;
  const S raw = m.damping_cap == DampingCap::elastic
                    ? S(c.elastic_force + min_of(c.elastic_force * ratio, c.elastic_force))
                    : S(c.elastic_force * (1.0 + ratio));  // eq. 3.14 | eq. 3.6
  c.normal_force = max_of(raw, 0.0);
  c.normal_force_on_ball = -c.normal_force * p.along_ball;
  if constexpr (std::is_same_v<S, double>)
    c.potential = rodend::elastic_energy(m, c.penetration, c.elastic_force);
  c.damping_power = (c.normal_force - c.elastic_force) * c.penetration_rate;
  return c.normal_force_on_ball;
}

/// Slip velocity v_t of the ball's contact point relative to the socket's, along the contact
/// plane of unit normal n (thesis 3.12-3.13): each sphere's own omega x r.
template <class S>
Vec3T<S> slip_velocity(const ClearanceContactModel& m, const BodyKinematicsT<S>& ball,
                       const BodyKinematicsT<S>& socket, const Vec3T<S>& n) {
  const Vec3T<S> v_rel = (ball.v_W + ball.w_W.cross(m.ball_radius * n)) -
                         (socket.v_W + socket.w_W.cross(m.socket_radius() * n));
  return v_rel - v_rel.dot(n) * n;
}

/// The contact; with kSliding false only its normal part (evaluate_normal_contact).
template <class S, bool kSliding = true>
ContactEvalT<S> evaluate(const ClearanceContactModel& m, const BodyKinematicsT<S>& ball,
                         const BodyKinematicsT<S>& socket, const ContactLatch& latch) {
  ContactEvalT<S> c;
  // eccentricity and penetration (thesis 3.1, 3.15), the local clearance on worn surfaces
  const Penetration<S> p = penetration(m, ball, socket);
  c.eccentricity = p.eccentricity;
  c.local_clearance = p.clearance;
  c.penetration = p.value();
  if (p.centred) return c;  // concentric: no direction, no contact
  c.normal = p.normal;
  c.penetration_rate = p.rate(ball, socket);
  if (c.penetration <= 0.0) return c;
  // elastic part from the geometry and hysteresis damping of the law, clamped so it never pulls
  normal_force(m, p, latch, c);
  if constexpr (!kSliding) return c;

  // slip velocity of the ball's contact point relative to the socket's (thesis 3.12-3.13)
  const Vec3T<S> r_ball = m.ball_radius * c.normal;
  const Vec3T<S> r_socket = m.socket_radius() * c.normal;
  const Vec3T<S> v_t = slip_velocity(m, ball, socket, c.normal);
  c.slip_speed = v_t.norm();
  // switch, stuck in an episode: no law (the scene adds the force that holds the slip,
  // contact_stick.hpp); before the driver latched one, slipping
  const FrictionLaw* law = m.stick
                               ? (latch.slipping || !latch.in_contact ? m.slipping_law() : nullptr)
                           : !m.branches.stuck ? m.friction.get()
                           : latch.slipping    ? m.branches.slipping.get()
                                               : m.branches.stuck.get();
  if (law && c.slip_speed > 0.0 && c.normal_force > 0.0) {
    const S mu = friction_coefficient(*law, c.slip_speed);
    c.friction_on_ball = -(mu * c.normal_force / c.slip_speed) * v_t;
    // friction moment r x F_t with each sphere's own radius (model-notes §1)
    c.moment_on_ball = r_ball.cross(c.friction_on_ball);
    c.moment_on_socket = r_socket.cross(-c.friction_on_ball);
    c.friction_power = mu * c.normal_force * c.slip_speed;
  }
  if (m.worn) {  // the normal force's moments on a worn surface (see Penetration)
    c.moment_on_ball -= c.normal_force * p.turn_ball;
    c.moment_on_socket -= c.normal_force * p.turn_socket;
  }
  return c;
}

}  // namespace rodend::contact_detail

namespace rodend {

/// The contact on dual numbers (the double one is evaluate_contact, contact.hpp).
template <int N>
ContactEvalT<Dual<N>> evaluate_contact(const ClearanceContactModel& m,
                                       const BodyKinematicsT<Dual<N>>& ball,
                                       const BodyKinematicsT<Dual<N>>& socket,
                                       const ContactLatch& latch) {
  return contact_detail::evaluate(m, ball, socket, latch);
}

}  // namespace rodend
