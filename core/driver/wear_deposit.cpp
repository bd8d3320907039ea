// The driver's wear stage: the sliding power of every accepted step, integrated on the step's
// interpolant and handed to the observer (scenes with a wear model, observers that want it).
#include <cmath>
#include <sstream>

#include "core/driver/run.hpp"

namespace rodend::detail {

/// Wear of the accepted step just taken, by 3-point Gauss-Legendre on its interpolant (exact
/// for polynomials of degree 5, the dense output's order; the sliding power is smooth within
/// a step, whose ends the driver places at contact onsets).
void deposit_wear(Run& run) {
  if (!run.model.wears) return;
  Stepper& stepper = run.stepper();
  RunState& s = run.state;
  const double t0 = stepper.t_prev, t1 = stepper.t_now, h = t1 - t0;
  if (!(h > 0.0)) return;
  static const double r = std::sqrt(0.6);
  static constexpr double w[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double node[3] = {-r, 0.0, r};
  for (int k = 0; k < 3; ++k) {
    const double t = t0 + 0.5 * h * (1.0 + node[k]);
    stepper.interpolate(t, s.z_tmp);
    run.model.unscale(s.z_tmp, s.x);
    const WearSource src = run.model.scene.wear_source(t, s.x.data(), s.discrete);
    if (!std::isfinite(src.sliding_power)) {
      std::ostringstream m;
      m << "non-finite sliding power at t = " << t << " s";
      throw RunFailure{RunStatus::non_finite_state, m.str()};
    }
    run.obs.on_wear(src, 0.5 * h * w[k]);
  }
}

}  // namespace rodend::detail
