// The driver's event-location stage: after each step, the earliest time inside it at which a
// contact changes state (an onset, a separation, or the deepest point of an impact's first
// step), from the method's own root finding (CVODE) or located on the step's interpolant.
#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/driver/argmax.hpp"
#include "core/driver/run.hpp"

namespace rodend::detail {
namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

/// Whether contact c, at t on the last step's interpolant, is in the other state than its
/// latch: penetrating while unlatched, or out of contact while latched.
bool changed_at(Run& run, int c, double t) {
  run.stepper().interpolate(t, run.state.z_tmp);
  const double p = gap_at(run, c, run.state.z_tmp).penetration;
  return latched(run, c) ? p <= 0.0 : p > 0.0;
}

/// The cubic Hermite model of a penetration over a step, from its values p0, p1 and scaled
/// rates m0 = h p'0, m1 = h p'1 at the two ends (exact for a free flight: a quadratic):
/// p(s) = (2s^3 - 3s^2 + 1) p0 + (s^3 - 2s^2 + s) m0 + (3s^2 - 2s^3) p1 + (s^3 - s^2) m1,
/// s in [0, 1]. Returns where inside the step it is largest (onset: `above` true; positive
/// there) or smallest (separation; <= 0 there), or -1 when it does not get there.
double hermite_crossing(double p0, double m0, double p1, double m1, bool above) {
  auto p = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (3 * s2 - 2 * s3) * p1 +
           (s3 - s2) * m1;
  };
  // p'(s) = a s^2 + b s + c
  const double a = 6 * p0 + 3 * m0 - 6 * p1 + 3 * m1, b = -6 * p0 - 4 * m0 + 6 * p1 - 2 * m1;
  const double c = m0;
  double roots[2] = {-1.0, -1.0};
  if (std::abs(a) < 1e-14 * (std::abs(b) + std::abs(c))) {
    if (b != 0.0) roots[0] = -c / b;
  } else if (const double d = b * b - 4 * a * c; d >= 0.0) {
    const double q = -0.5 * (b + std::copysign(std::sqrt(d), b));  // no cancellation
    roots[0] = q / a;
    if (q != 0.0) roots[1] = c / q;
  }
  double best = -1.0;
  for (double s : roots)
    if (s > 0.0 && s < 1.0 && (above ? p(s) > 0.0 : p(s) <= 0.0) &&
        (best < 0.0 || (above ? p(s) > p(best) : p(s) < p(best))))
      best = s;
  return best;
}

/// Where contact c penetrates deepest in the last step, on its interpolant (+inf if it does
/// not penetrate): the first step of an episode that went past its deepest point (or through
/// the whole episode) is split there, so that every impact has a step end at its peak. An
/// error estimate from nodes at the step ends alone (Fehlberg 7(8): err ~ k1 + k11 - k12 -
/// k13, nodes at 0, 1, 0, 1) does not see an impact between them.
double deepest_time(Run& run, int c) {
  Stepper& stepper = run.stepper();
  const double t0 = stepper.t_prev, t1 = stepper.t_now;
  double p_max = 0.0;
  const double t = argmax(
      t0, t1, 1e-3 * (t1 - t0),
      [&](double tt) {
        stepper.interpolate(tt, run.state.z_tmp);
        return gap_at(run, c, run.state.z_tmp).penetration;
      },
      p_max);
  return p_max > 0.0 && t < t1 ? t : kNone;
}

/// Bisection of a change of contact c bracketed by (lo, hi], on the method's own interpolant
/// (consistent with the re-take); 60 halvings reach the resolution of double time for any
/// step length.
double bisect_change(Run& run, int c, double lo, double hi) {
  for (int it = 0; it < 60 && hi - lo > 4e-16 * std::max(1.0, std::abs(hi)); ++it) {
    const double mid = 0.5 * (lo + hi);
    (changed_at(run, c, mid) ? hi : lo) = mid;
  }
  return hi;
}

/// The earliest time in (t_prev, t_now] at which contact c changes state on the step's
/// interpolant, or +inf. A change at the step end is bracketed by the step; a change inside
/// it with neither end changed (an impact stepped over, or a separation followed by a new
/// onset) by the Hermite model's extremum, confirmed on the interpolant; then bisection.
double change_time(Run& run, int c) {
  const Stepper& stepper = run.stepper();
  const bool in = latched(run, c);
  const ContactGap g0 = end_gap(run, c, stepper.z_prev), g1 = end_gap(run, c, stepper.z_now);
  if (in && !run.state.touched[static_cast<std::size_t>(c)] && g1.penetration_rate < 0.0)
    return deepest_time(run, c);
  auto changed = [in](double p) { return in ? p <= 0.0 : p > 0.0; };
  if (changed(g0.penetration)) return kNone;  // at a restart point: latched at the step end
  const double t0 = stepper.t_prev, h = stepper.t_now - t0;
  double hi = stepper.t_now;
  if (changed(g1.penetration)) {
    if (in) return kNone;  // a separation at the step end is latched there (accept_step)
  } else {
    // candidates: the Hermite model's extremum, and (onsets) the earliest stage that felt one
    const double s = hermite_crossing(g0.penetration, h * g0.penetration_rate, g1.penetration,
                                      h * g1.penetration_rate, !in);
    const double t_stage = in ? kNone : run.state.watch.earliest;
    hi = kNone;
    for (double t : {s >= 0.0 ? t0 + s * h : kNone, t_stage})
      if (hi == kNone && t > t0 && t < stepper.t_now && changed_at(run, c, t)) hi = t;
    if (hi == kNone) return kNone;  // the method's own solution does not change
  }
  return bisect_change(run, c, t0, hi);
}

}  // namespace

/// The event of the last step: the roots the method found itself (CVODE), else the earliest
/// contact change located on the step (integrator.contact_onset "locate"); t = t_now if none.
Event find_event(Run& run) {
  const Stepper& stepper = run.stepper();
  Event ev;
  ev.t = stepper.t_now;
  if (stepper.finds_roots() && !stepper.roots.empty()) {
    ev.contacts = stepper.roots;
    ev.from_method = true;
    return ev;
  }
  if (run.model.settings.contact_onset != ContactOnset::locate ||
      std::exchange(run.state.locate_suspended, false))
    return ev;
  for (int c = 0; c < run.model.scene.contact_count(); ++c) {
    const double t = change_time(run, c);
    if (t < ev.t) ev.contacts.clear();
    if (t <= ev.t && t < stepper.t_now) {
      ev.t = t;
      ev.contacts.push_back(c);
    }
  }
  const double earliest = run.state.watch.earliest;
  if (ev.contacts.empty() && earliest > stepper.t_prev && earliest < stepper.t_now) {
    ev.t = earliest;
    ev.stage_only = true;
  }
  return ev;
}

}  // namespace rodend::detail
