// Restitution-matched law: chi(c_r) solved numerically so that a free impact restitutes exactly
// the requested c_r. Undefined at c_r = 0 (it would need chi = infinity).
//
// Why it can be done once for every mass, speed and stiffness: for a pure power law
// F = K delta^n (1 + chi delta'/delta'^-) and two bodies of reduced mass m meeting at speed v
// (or one body on a fixed one), delta = d x and t = (d/v) tau with d = (m v^2/K)^(1/(n+1)) give
//     x'' = -x^n (1 + chi x'),   x(0) = 0,  x'(0) = 1,
// free of m, v and K: the achieved restitution e = -x'(end of contact) depends on chi and n
// only (n = 1.5, both geometries of contact.hpp). So chi(c_r) is the root of e(chi) = c_r.
//
// Properties used by the solver:
//  - g = 1 + chi x' obeys g' = chi x'' = -chi x^n g, so g never reaches 0: the no-pull clamp
//    never acts in a free impact, and the exit speed stays below 1/chi, i.e. e(chi) < 1/chi.
//    Hence [0, 1/c_r] brackets the root (e(0) = 1 >= c_r, e(1/c_r) < c_r).
//  - e(chi) decreases with chi (more damping, less rebound).
// e(chi) is integrated with Dormand-Prince 5(4) at abs/rel 1e-13 with dense output; the end of
// contact (x back to 0) is located on the interpolant by bisection, and x' read there. The root
// is found by the Illinois variant of regula falsi to |e - c_r| <= 1e-11.
// Residual: e(chi) is reproduced to ~1e-11 (checked against classical RK4 at dtau = 1e-4 in
// tests/test_impact_pair.cpp), so the law restitutes c_r to that, up to the simulator's own
// integration error. It is exact for the sphere (pure power law); on the cylinder geometry,
// F_el ~ delta^1.5 (1 - delta/(2 dR) + ...), so the match is off by O(delta_max/dR), under
// 1e-3 for the impacts of the shipped scenes.
//
// Cost: ~20 solves of a ~100-step integration, well under a millisecond, once per scene built.
#include <array>
#include <boost/numeric/odeint.hpp>
#include <cmath>

#include "core/contact.hpp"

namespace rodend {
namespace {

namespace odeint = boost::numeric::odeint;
using State = std::array<double, 2>;  // x, x'

constexpr double kExponent = 1.5;

class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "restitution-matched"; }
  double hysteresis_factor(double cr) const override {
    if (cr >= 1.0) return 0.0;
    // Illinois regula falsi on f(chi) = e(chi) - c_r over [0, 1/c_r]
    double a = 0.0, fa = 1.0 - cr;
    double b = 1.0 / cr, fb = dimensionless_impact_restitution(b, kExponent) - cr;
    // for small c_r, e(1/c_r) is within round-off of c_r (e -> 1/chi as chi grows): then 1/c_r
    // is the root to that accuracy
    if (!(fb < 0.0)) return b;
    int side = 0;
    double c = b;
    for (int it = 0; it < 200; ++it) {
      c = (a * fb - b * fa) / (fb - fa);
      const double fc = dimensionless_impact_restitution(c, kExponent) - cr;
      if (std::abs(fc) <= 1e-11 || b - a <= 1e-15 * b) break;
      if ((fc > 0.0) == (fa > 0.0)) {
        a = c;
        fa = fc;
        if (side == -1) fb *= 0.5;
        side = -1;
      } else {
        b = c;
        fb = fc;
        if (side == +1) fa *= 0.5;
        side = +1;
      }
    }
    return c;
  }
  bool defined_at_zero_restitution() const override { return false; }
};

}  // namespace

double dimensionless_impact_restitution(double chi, double n) {
  const auto rhs = [chi, n](const State& s, State& ds, double) {
    ds[0] = s[1];
    // no force across a gap; g = 1 + chi x' stays > 0 (see above), clamped all the same
    ds[1] = s[0] > 0.0 ? -std::pow(s[0], n) * std::max(1.0 + chi * s[1], 0.0) : 0.0;
  };
  auto stepper = odeint::make_dense_output(1e-13, 1e-13, odeint::runge_kutta_dopri5<State>());
  stepper.initialize(State{0.0, 1.0}, 0.0, 1e-3);
  State s{};
  for (int i = 0; i < 1'000'000; ++i) {
    stepper.do_step(rhs);
    const State& now = stepper.current_state();
    if (now[0] < 0.0 && now[1] < 0.0) {
      // back through x = 0: locate it on the interpolant and read the speed there
      double lo = stepper.previous_time(), hi = stepper.current_time();
      for (int k = 0; k < 80 && hi - lo > 1e-15 * hi; ++k) {
        const double mid = 0.5 * (lo + hi);
        stepper.calc_state(mid, s);
        (s[0] > 0.0 ? lo : hi) = mid;
      }
      stepper.calc_state(hi, s);
      return -s[1];
    }
  }
  return std::nan("");  // never ends (cannot happen for chi < infinity)
}

const NormalLaw& restitution_matched_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
