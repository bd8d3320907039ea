#include "core/contact.hpp"

#include "core/contact_eval.hpp"

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

double elastic_force(const ClearanceContactModel& m, double delta) {
  return contact_detail::elastic_force(m, delta);
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

double smooth_step_slope(double x, double x0, double f0, double x1, double f1) {
  if (x <= x0 || x >= x1) return 0.0;
  const double u = (x - x0) / (x1 - x0);
  return (f1 - f0) * 6.0 * u * (1.0 - u) / (x1 - x0);
}

ContactGap contact_gap(const ClearanceContactModel& m, const BodyKinematics& ball,
                       const BodyKinematics& socket) {
  const auto p = contact_detail::penetration(m, ball, socket);
  if (p.centred) return {-p.clearance, 0.0};
  ContactGap g{p.value(), p.rate(ball, socket)};
  if (m.branches.stuck && g.penetration > 0.0)  // friction.mode stick-slip: the branch due
    g.slipping = contact_detail::slip_velocity(m, ball, socket, p.normal).norm() > m.switch_speed;
  return g;
}

ContactEval evaluate_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                             const BodyKinematics& socket, const ContactLatch& latch) {
  return contact_detail::evaluate(m, ball, socket, latch);
}

ContactEval evaluate_normal_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                                    const BodyKinematics& socket, const ContactLatch& latch) {
  return contact_detail::evaluate<double, false>(m, ball, socket, latch);
}

}  // namespace rodend
