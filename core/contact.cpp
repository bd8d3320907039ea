#include "core/contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace rodend {

double effective_modulus(double Eb, double nub, double Es, double nus) {
  return 1.0 / ((1.0 - nub * nub) / Eb + (1.0 - nus * nus) / Es);
}

double sphere_in_sphere_stiffness(double Rb, double Rs, double Eb, double nub, double Es,
                                  double nus) {
  // written out (not through effective_modulus) so the defaults stay bit-identical
  const double inv_E = (1.0 - nub * nub) / Eb + (1.0 - nus * nus) / Es;
  const double R_eff = Rb * Rs / (Rs - Rb);
  return 4.0 / 3.0 / inv_E * std::sqrt(R_eff);
}

double cylinder_in_cylinder_coefficient(double L, double Eb, double nub, double Es, double nus) {
  return 0.5 * std::numbers::pi * L * effective_modulus(Eb, nub, Es, nus);
}

namespace {

/// delta^n; the Hertz exponent 1.5 of both geometries as delta sqrt(delta) (no pow call).
double power_law(double delta, double n) {
  return n == 1.5 ? delta * std::sqrt(delta) : std::pow(delta, n);
}

}  // namespace

double elastic_force(const ClearanceContactModel& m, double delta) {
  switch (m.geometry) {
    case ContactGeometry::sphere:
      return m.stiffness * power_law(delta, m.exponent);
    case ContactGeometry::cylinder:
      return m.stiffness * power_law(delta, m.exponent) / std::sqrt(2.0 * (m.clearance + delta));
  }
  return 0.0;
}

namespace {

/// The integral from 0 to delta of u^n (c + u)^(-1/2) du, c > 0.
///  delta < c/2: the binomial series c^(-1/2) delta^(n+1) sum_k binom(-1/2, k) r^k / (n+1+k),
///    r = delta/c (each term at most half the previous: 55 terms reach round-off);
///  beyond (n = 1.5 only, the flap-actuation study's exponent): u = c sinh^2 t turns it into
///    2 c^2 int_0^T sinh^4 t dt = 2 c^2 (3T/8 - sinh(2T)/4 + sinh(4T)/32), T = asinh(sqrt(r)),
///    whose terms cancel only mildly for T >= asinh(sqrt(1/2)).
double cylinder_energy_integral(double delta, double c, double n) {
  const double r = delta / c;
  if (r < 0.5 || n != 1.5) {
    double term = 1.0, sum = 0.0;
    for (int k = 0; k < 200; ++k) {
      const double add = term / (n + 1.0 + k);
      sum += add;
      if (std::abs(add) <= 1e-17 * std::abs(sum)) break;
      term *= -r * (2.0 * k + 1.0) / (2.0 * k + 2.0);
    }
    return std::pow(delta, n + 1.0) / std::sqrt(c) * sum;
  }
  const double T = std::asinh(std::sqrt(r));
  return 2.0 * c * c * (0.375 * T - 0.25 * std::sinh(2.0 * T) + std::sinh(4.0 * T) / 32.0);
}

}  // namespace

double elastic_energy(const ClearanceContactModel& m, double delta, double force) {
  switch (m.geometry) {
    case ContactGeometry::sphere:
      return force * delta / (m.exponent + 1.0);
    case ContactGeometry::cylinder:
      return m.stiffness / std::numbers::sqrt2 *
             cylinder_energy_integral(delta, m.clearance, m.exponent);
  }
  return 0.0;
}

double smooth_step(double x, double x0, double f0, double x1, double f1) {
  if (x <= x0) return f0;
  if (x >= x1) return f1;
  const double u = (x - x0) / (x1 - x0);
  return f0 + (f1 - f0) * u * u * (3.0 - 2.0 * u);
}

namespace {

/// The penetration delta = |e| - c(n) of a contact and its gradient. Without worn surfaces
/// c(n) = c and the gradient is the contact normal. With them, c(n) = c + h_b(R_b^T n) +
/// h_s(R_s^T n), and
///   d delta / d p_ball        = n - (g_b + g_s) / |e|      (= - d delta / d p_socket)
///   d delta / d theta_ball    = n x g_b                     (small rotation of the ball, world)
///   d delta / d theta_socket  = n x g_s
/// with g the map gradients with respect to the direction (world frame): the normal force
/// F_n acts on each body along minus these, so the contact stays conservative (the work of
/// F_el is minus the change of its potential) on a worn, non-spherical surface.
struct Penetration {
  Vec3 normal = Vec3::UnitX();
  double eccentricity = 0.0;
  double clearance = 0.0;  ///< local clearance c(n) [m]
  Vec3 along_ball = Vec3::UnitX();
  Vec3 turn_ball = Vec3::Zero(), turn_socket = Vec3::Zero();
  bool centred = false;  ///< concentric: no direction
  double value() const { return eccentricity - clearance; }
  double rate(const BodyKinematics& ball, const BodyKinematics& socket) const {
    return along_ball.dot(ball.v_W - socket.v_W) + turn_ball.dot(ball.w_W) +
           turn_socket.dot(socket.w_W);
  }
};

Penetration penetration(const ClearanceContactModel& m, const BodyKinematics& ball,
                        const BodyKinematics& socket) {
  Penetration p;
  const Vec3 d = ball.p_W - socket.p_W;  // socket centre -> ball centre
  p.eccentricity = d.norm();
  p.clearance = m.clearance;
  if (p.eccentricity < 1e-300) {
    p.centred = true;
    return p;
  }
  p.normal = d / p.eccentricity;
  p.along_ball = p.normal;
  if (m.worn) {
    Vec3 gb, gs;
    p.clearance += m.worn->extra_clearance(p.normal, ball.R_WB, socket.R_WB, &gb, &gs);
    p.along_ball -= (gb + gs) / p.eccentricity;
    p.turn_ball = p.normal.cross(gb);
    p.turn_socket = p.normal.cross(gs);
  }
  return p;
}

}  // namespace

ContactGap contact_gap(const ClearanceContactModel& m, const BodyKinematics& ball,
                       const BodyKinematics& socket) {
  const Penetration p = penetration(m, ball, socket);
  if (p.centred) return {-p.clearance, 0.0};
  return {p.value(), p.rate(ball, socket)};
}

ContactEval evaluate_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                             const BodyKinematics& socket, const ContactLatch& latch) {
  ContactEval c;
  // eccentricity and penetration (thesis 3.1, 3.15), the local clearance on worn surfaces
  const Penetration p = penetration(m, ball, socket);
  c.eccentricity = p.eccentricity;
  c.local_clearance = p.clearance;
  c.penetration = p.value();
  if (p.centred) return c;  // concentric: no direction, no contact
  c.normal = p.normal;
  c.penetration_rate = p.rate(ball, socket);
  if (c.penetration <= 0.0) return c;

  // elastic part from the geometry (thesis 3.3; model-notes §3) and hysteresis damping of the
  // law (3.6-3.8), clamped so it never pulls
  c.elastic_force = elastic_force(m, c.penetration);
  const double approach = latch.in_contact ? latch.impact_speed : std::abs(c.penetration_rate);
  const double impact_speed = std::max(approach, m.min_impact_speed);
  const double ratio = m.hysteresis * c.penetration_rate / impact_speed;
  const double raw = m.damping_cap == DampingCap::elastic
                         ? c.elastic_force + std::min(c.elastic_force * ratio, c.elastic_force)
                         : c.elastic_force * (1.0 + ratio);  // eq. 3.14 | eq. 3.6
  c.normal_force = std::max(raw, 0.0);
  c.normal_force_on_ball = -c.normal_force * p.along_ball;
  c.potential = elastic_energy(m, c.penetration, c.elastic_force);
  c.damping_power = (c.normal_force - c.elastic_force) * c.penetration_rate;

  // slip velocity of the ball's contact point relative to the socket's (thesis 3.12-3.13)
  const Vec3 r_ball = m.ball_radius * c.normal;
  const Vec3 r_socket = m.socket_radius() * c.normal;
  const Vec3 v_rel =
      (ball.v_W + ball.w_W.cross(r_ball)) - (socket.v_W + socket.w_W.cross(r_socket));
  const Vec3 v_t = v_rel - v_rel.dot(c.normal) * c.normal;
  c.slip_speed = v_t.norm();
  if (m.friction && c.slip_speed > 0.0 && c.normal_force > 0.0) {
    const double mu = m.friction->coefficient(c.slip_speed);
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

}  // namespace rodend
