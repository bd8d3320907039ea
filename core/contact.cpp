#include "core/contact.hpp"

#include <algorithm>
#include <cmath>

namespace rodend {

double sphere_in_sphere_stiffness(double Rb, double Rs, double Eb, double nub, double Es,
                                  double nus) {
  const double inv_E = (1.0 - nub * nub) / Eb + (1.0 - nus * nus) / Es;
  const double R_eff = Rb * Rs / (Rs - Rb);
  return 4.0 / 3.0 / inv_E * std::sqrt(R_eff);
}

double smooth_step(double x, double x0, double f0, double x1, double f1) {
  if (x <= x0) return f0;
  if (x >= x1) return f1;
  const double u = (x - x0) / (x1 - x0);
  return f0 + (f1 - f0) * u * u * (3.0 - 2.0 * u);
}

ContactGap contact_gap(const SphericalContactModel& m, const BodyKinematics& ball,
                       const BodyKinematics& socket) {
  const Vec3 d = ball.p_W - socket.p_W;  // socket centre -> ball centre
  const double e = d.norm();
  if (e < 1e-300) return {-m.clearance, 0.0};
  const Vec3 n = d / e;
  return {e - m.clearance, n.dot(ball.v_W - socket.v_W)};
}

ContactEval evaluate_contact(const SphericalContactModel& m, const BodyKinematics& ball,
                             const BodyKinematics& socket, const ContactLatch& latch) {
  ContactEval c;
  // eccentricity and penetration (thesis 3.1, 3.15)
  const Vec3 d = ball.p_W - socket.p_W;
  c.eccentricity = d.norm();
  c.penetration = c.eccentricity - m.clearance;
  if (c.eccentricity < 1e-300) return c;  // concentric: no direction, no contact
  c.normal = d / c.eccentricity;
  c.penetration_rate = c.normal.dot(ball.v_W - socket.v_W);
  if (c.penetration <= 0.0) return c;

  // elastic part (thesis 3.3) and hysteresis damping (3.6-3.8), clamped so it never pulls
  c.elastic_force = m.stiffness * std::pow(c.penetration, m.exponent);
  const double approach =
      latch.in_contact ? latch.impact_speed : std::abs(c.penetration_rate);
  const double impact_speed = std::max(approach, m.min_impact_speed);
  const double raw =
      c.elastic_force * (1.0 + m.hysteresis * c.penetration_rate / impact_speed);
  c.normal_force = std::max(raw, 0.0);
  c.normal_force_on_ball = -c.normal_force * c.normal;
  c.potential = c.elastic_force * c.penetration / (m.exponent + 1.0);
  c.damping_power = (c.normal_force - c.elastic_force) * c.penetration_rate;

  // slip velocity of the ball's contact point relative to the socket's (thesis 3.12-3.13)
  const Vec3 r_ball = m.ball_radius * c.normal;
  const Vec3 r_socket = m.socket_radius() * c.normal;
  const Vec3 v_rel = (ball.v_W + ball.w_W.cross(r_ball)) - (socket.v_W + socket.w_W.cross(r_socket));
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
  return c;
}

}  // namespace rodend
