// Restitution-matched law: chi(c_r) chosen so that a free impact restitutes exactly the
// requested c_r, for either geometry. Undefined at c_r = 0 (it would need chi = infinity).
//
// Why one relation holds for every geometry, mass and speed. In a free impact (two bodies, or
// one on a fixed one, reduced mass m, nothing else acting) the pipeline of contact.hpp gives
//     m delta'' = -F_el(delta) (1 + chi delta'/v),   v = delta'^- (latched at the onset).
// Multiply by delta' and divide by (1 + chi delta'/v):  m delta' d(delta') / (1 + chi delta'/v)
// = -F_el(delta) d(delta). Over the whole contact delta goes from 0 back to 0, so the right
// side integrates to 0 whatever F_el is (sphere, cylinder, any exponent), and with w = delta'/v
// going from 1 to -e:
//     int_{-e}^{1} w / (1 + chi w) dw = 0   <=>   ln((1 + chi) / (1 - chi e)) = chi (1 + e).
// The division is legitimate: g = 1 + chi delta'/v obeys g' = -(chi/(m v)) F_el g, so g never
// reaches 0 and the no-pull clamp never acts in a free impact (also e < 1/chi).
// The achieved restitution e therefore depends on chi alone (for an approach speed above the
// guard contact.min_impact_speed, below which the damping uses the guard instead of v).
// Expanding for small chi gives chi = 3 (1 - e^2) / (2 (1 + e^3)) + ..., whose leading term
// near e = 1 is Lankarani-Nikravesh's 3 (1 - e^2) / 4: the published laws are approximations of
// this relation, good near c_r = 1 (see the README's "Contact laws").
//
// Numerics: the relation is solved by bisection to the last bits (about 60 halvings), on
// G(chi, e) = [ln(1 + chi) - ln(1 - e chi) - chi (1 + e)] / chi^2, which removes the trivial root
// chi = 0; for chi <= 0.05 G is summed from its series sum_{k>=2} ((-1)^(k+1) + e^k) chi^(k-2)/k
// (no cancellation). G(., e) < 0 below the root and > 0 above it (the numerator is concave then
// convex in chi), and G(chi, .) increases with e. Residual: round-off only (checked in
// tests/test_impact_pair.cpp against a direct integration of the impact, and through the
// simulator to 1e-7).
#include <cmath>

#include "core/contact.hpp"

namespace rodend {
namespace {

/// G(chi, e) above, for chi > 0, 0 <= e <= 1, e chi < 1.
double relation(double chi, double e) {
  if (chi <= 0.05) {
    double sum = 0.0, chi_pow = 1.0, e_pow = e;  // chi^(k-2), e^(k-1)
    for (int k = 2; k <= 18; ++k) {
      e_pow *= e;
      sum += ((k % 2 == 1 ? 1.0 : -1.0) + e_pow) * chi_pow / k;
      chi_pow *= chi;
    }
    return sum;
  }
  return (std::log1p(chi) - std::log1p(-e * chi) - chi * (1.0 + e)) / (chi * chi);
}

class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "restitution-matched"; }
  std::string_view description() const override {
    return "chi(c_r) such that a free impact restitutes exactly c_r, for either geometry; "
           "undefined at c_r = 0";
  }
  double hysteresis_factor(double cr) const override { return hysteresis_for_restitution(cr); }
  bool defined_at_zero_restitution() const override { return false; }
};

}  // namespace

double free_impact_restitution(double chi) {
  if (!(chi > 0.0)) return 1.0;
  double lo = 0.0, hi = std::min(1.0, 1.0 / chi);
  for (int it = 0; it < 200 && hi - lo > 2e-16 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (1.0 - chi * mid <= 0.0 || relation(chi, mid) >= 0.0)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

double hysteresis_for_restitution(double e) {
  if (e >= 1.0) return 0.0;
  if (!(e > 0.0)) return INFINITY;
  double lo = 0.0, hi = 1.0 / e;
  for (int it = 0; it < 200 && hi - lo > 2e-16 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (1.0 - e * mid <= 0.0 || relation(mid, e) >= 0.0)
      hi = mid;
    else
      lo = mid;
  }
  // for small e the root lies within round-off of 1/e (1 - e chi = (1 + chi) exp(-chi (1 + e)),
  // e.g. 2e-42 at e = 0.01): the bracket then closes on 1/e itself
  return 0.5 * (lo + hi);
}

const NormalLaw& restitution_matched_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
