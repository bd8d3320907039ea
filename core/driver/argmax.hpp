// Internal to the driver: the maximum of a function on an interval (Brent's method), used to
// locate a contact's deepest point (core/driver/events.cpp) and its peaks
// (core/driver/peaks.cpp) on a step's interpolant.
#pragma once

#include <cmath>

namespace rodend::detail {

/// The maximum of f on [a, b] (Brent's method: golden section with parabolic steps), to the
/// time resolution `tol` [s]; returns its time and writes its value.
template <class F>
double argmax(double a, double b, double tol, F&& f, double& f_max) {
  const double golden = 0.5 * (3.0 - std::sqrt(5.0));
  double x = a + golden * (b - a), w = x, v = x;
  double fx = -f(x), fw = fx, fv = fx;  // minimising -f
  double d = 0.0, e = 0.0;
  for (int it = 0; it < 100; ++it) {
    const double m = 0.5 * (a + b);
    const double tol1 = tol + 4e-16 * std::abs(x), tol2 = 2.0 * tol1;
    if (std::abs(x - m) <= tol2 - 0.5 * (b - a)) break;
    bool golden_step = true;
    if (std::abs(e) > tol1) {  // try a parabola through x, w, v
      double r = (x - w) * (fx - fv), q = (x - v) * (fx - fw), p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0)
        p = -p;
      else
        q = -q;
      const double e_old = e;
      e = d;
      if (std::abs(p) < std::abs(0.5 * q * e_old) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < tol2 || b - u < tol2) d = m - x >= 0.0 ? tol1 : -tol1;
        golden_step = false;
      }
    }
    if (golden_step) {
      e = x >= m ? a - x : b - x;
      d = golden * e;
    }
    const double u = std::abs(d) >= tol1 ? x + d : x + (d >= 0.0 ? tol1 : -tol1);
    const double fu = -f(u);
    if (fu <= fx) {
      (u >= x ? a : b) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  f_max = -fx;
  return x;
}

}  // namespace rodend::detail
