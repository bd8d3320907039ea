// The driver's contact-peak stage: the maxima of each contact's normal force and penetration
// inside an accepted step, located on the step's interpolant when the observer wants them.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/driver/argmax.hpp"
#include "core/driver/run.hpp"

namespace rodend::detail {
namespace {

/// The accepted step just taken: its ends, the time offset of the force's one-sided slopes and
/// the time resolution of a located maximum [s].
struct Span {
  double t0, t1, eps, tol;
};

/// Contact c at time t of the last step, on its interpolant (at its end, the step's state).
ContactSnapshot snapshot_at(Run& run, int c, double t) {
  Stepper& stepper = run.stepper();
  RunState& s = run.state;
  if (t >= stepper.t_now)
    s.z_tmp = stepper.z_now;
  else
    stepper.interpolate(t, s.z_tmp);
  run.model.unscale(s.z_tmp, s.x);
  return run.model.scene.contact_snapshot(c, t, s.x.data(), s.discrete);
}

/// Where the tangents at (t0, f0) with slope s0 > 0 and at (t1, f1) with slope s1 < 0 meet:
/// an upper bound of the maximum in between when f is concave there.
double tangent_bound(double t0, double f0, double s0, double t1, double f1, double s1) {
  const double t = (f1 - f0 + s0 * t0 - s1 * t1) / (s0 - s1);
  return f0 + s0 * (std::clamp(t, t0, t1) - t0);
}

void report_peak(Run& run, ContactPeak::Kind kind, int c, double t) {
  ContactPeak p;
  p.kind = kind;
  p.contact = c;
  p.t = t;
  p.at = snapshot_at(run, c, t);
  for (double v : {p.at.penetration, p.at.penetration_rate, p.at.eccentricity, p.at.normal_force})
    if (!std::isfinite(v)) {
      std::ostringstream m;
      m << "non-finite contact state at t = " << t << " s";
      throw RunFailure{RunStatus::non_finite_state, m.str()};
    }
  run.obs.on_contact_peak(p);
}

/// The maximum of the normal force, where its slope turns from rising to falling (with
/// damping this is before the maximum penetration). The slopes at the step ends are one-sided
/// differences over eps; the end's is carried to the next step's start.
void force_peak(Run& run, int c, const Span& sp, ContactEnd& start, ContactEnd& end) {
  end.force_slope =
      (end.at.normal_force - snapshot_at(run, c, sp.t1 - sp.eps).normal_force) / sp.eps;
  end.force_slope_known = true;
  if (!start.force_slope_known) {
    start.force_slope =
        (snapshot_at(run, c, sp.t0 + sp.eps).normal_force - start.at.normal_force) / sp.eps;
    start.force_slope_known = true;
  }
  if (!(start.force_slope > 0.0 && end.force_slope < 0.0)) return;
  const double bound = tangent_bound(sp.t0, start.at.normal_force, start.force_slope, sp.t1,
                                     end.at.normal_force, end.force_slope);
  if (!run.obs.wants_peak(ContactPeak::Kind::force, c, sp.t0, bound)) return;
  double f_max = 0.0;
  const double t = argmax(
      sp.t0, sp.t1, sp.tol, [&](double tt) { return snapshot_at(run, c, tt).normal_force; }, f_max);
  report_peak(run, ContactPeak::Kind::force, c, t);
}

/// The maximum of the penetration, where its rate (the state's) turns from positive to
/// negative.
void penetration_peak(Run& run, int c, const Span& sp, const ContactEnd& start,
                      const ContactEnd& end) {
  if (!(start.at.penetration_rate > 0.0 && end.at.penetration_rate <= 0.0 &&
        std::max(start.at.penetration, end.at.penetration) > 0.0))
    return;
  const double bound =
      tangent_bound(sp.t0, start.at.penetration, start.at.penetration_rate, sp.t1,
                    end.at.penetration, std::min(end.at.penetration_rate, -1e-300));
  if (!run.obs.wants_peak(ContactPeak::Kind::penetration, c, sp.t0, bound)) return;
  double d_max = 0.0;
  const double t = argmax(
      sp.t0, sp.t1, sp.tol, [&](double tt) { return snapshot_at(run, c, tt).penetration; }, d_max);
  report_peak(run, ContactPeak::Kind::penetration, c, t);
}

}  // namespace

/// The peaks of an impact fall between step ends. For each contact, inside the accepted step
/// just taken: a maximum of the normal force and a maximum of the penetration, each located on
/// the step's interpolant (Brent) when the observer says it could change what it collects, and
/// reported to it.
void locate_contact_peaks(Run& run) {
  const double t0 = run.stepper().t_prev, t1 = run.stepper().t_now, h = t1 - t0;
  if (!(h > 0.0)) return;
  const Span sp{t0, t1, 1e-4 * h, 1e-7 * h};
  for (int c = 0; c < run.model.scene.contact_count(); ++c) {
    ContactEnd& last = run.state.ends[static_cast<std::size_t>(c)];
    ContactEnd start;
    if (last.valid && last.t == t0) {
      start = last;
    } else {
      start.at = snapshot_at(run, c, t0);
      start.force_slope_known = false;
    }
    ContactEnd end;
    end.t = t1;
    end.valid = true;
    end.at = snapshot_at(run, c, t1);
    if (run.model.provides_force && (start.at.normal_force > 0.0 || end.at.normal_force > 0.0))
      force_peak(run, c, sp, start, end);
    penetration_peak(run, c, sp, start, end);
    last = end;
  }
}

}  // namespace rodend::detail
