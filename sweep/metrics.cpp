#include "sweep/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace rodend {
namespace {

constexpr std::array<MetricSpec, metric_count> kMetrics{{
#define RODEND_METRIC(id, unit, doc) MetricSpec{#id, unit, doc},
#include "sweep/metrics.def"
#undef RODEND_METRIC
}};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class T>
bool provides(const Scene& s, T id) {
  const auto sig = s.signals();
  return std::find(sig.begin(), sig.end(), id) != sig.end();
}

double& at(MetricValues& v, MetricId id) {
  return v[static_cast<std::size_t>(id)];
}
double at(const MetricValues& v, MetricId id) {
  return v[static_cast<std::size_t>(id)];
}

}  // namespace

std::span<const MetricSpec> metric_catalogue() {
  return kMetrics;
}

MetricsAccumulator::MetricsAccumulator(const Scene& scene, const MetricsSettings& settings)
    : settings_(settings),
      has_contact_(scene.features().has(Feature::contact)),
      has_surface_(scene.features().has(Feature::mechanism)),
      has_energy_(scene.features().has(Feature::energy_audit)),
      has_chambers_(scene.features().has(Feature::actuator)),
      has_kinetic_(provides(scene, SignalId::kinetic_energy)),  // a term of the audit's scale
      has_command_(scene.features().has(Feature::mechanism)),
      has_crank_(provides(scene, SignalId::crank_angle) &&
                 provides(scene, SignalId::slider_acceleration)),
      has_joint_forces_(provides(scene, SignalId::joint_normal_forces)),
      has_crank_rate_(provides(scene, SignalId::surface_rate)),
      // the rod-extension command: the actuator's, else the prescribed motion itself
      command_signal_(scene.features().has(Feature::actuator) ? SignalId::actuator_command
                                                              : SignalId::actuator_position),
      linkage_(scene),
      periodic_(scene) {
  v_.fill(kNaN);
  if (has_crank_ && settings_.lowpass_cutoff > 0.0)
    lowpass_.emplace(settings_.lowpass_cutoff, settings_.lowpass_order);
  if (has_surface_ && provides(scene, SignalId::surface_acceleration))
    accel_hf_.emplace(settings_.feature_highpass, settings_.onset_window);
  if (has_chambers_ && has_contact_)
    pressure_hf_.emplace(settings_.feature_highpass, settings_.onset_window);
  if (has_contact_) {
    for (MetricId id : {MetricId::first_impact_peak_force, MetricId::max_contact_force,
                        MetricId::max_eccentricity, MetricId::max_penetration,
                        MetricId::contact_time, MetricId::wear_integral})
      at(v_, id) = 0.0;
    at(v_, MetricId::max_penetration) = -std::numeric_limits<double>::infinity();
  }
}

void MetricsAccumulator::on_step(const SignalFrame& f) {
  const double t = f.get(SignalId::time);
  const double dt = first_step_ ? 0.0 : t - t_prev_;
  if (has_contact_) step_contact(f, t, dt);
  if (has_surface_) step_surface(f, t);
  if (has_command_) step_command(f);
  if (has_chambers_) step_chambers(f);
  if (has_crank_) step_crank(f, t, dt);
  if (has_energy_) step_energy(f);
  if (periodic_.active()) periodic_.on_step(f);
  if (linkage_.active()) linkage_.on_step(f);
  if (accel_hf_) accel_hf_->add(t, f.get(SignalId::surface_acceleration));
  if (pressure_hf_) pressure_hf_->add(t, f.get(SignalId::chamber_pressures, 0));
  t_prev_ = t;
  first_step_ = false;
}

void MetricsAccumulator::step_contact(const SignalFrame& f, double t, double dt) {
  const double F = f.get(SignalId::contact_force);
  const double ecc = f.get(SignalId::eccentricity);
  const double wear = f.get(SignalId::wear_indicator);
  at(v_, MetricId::max_contact_force) = std::max(at(v_, MetricId::max_contact_force), F);
  at(v_, MetricId::max_eccentricity) = std::max(at(v_, MetricId::max_eccentricity), ecc);
  at(v_, MetricId::max_penetration) =
      std::max(at(v_, MetricId::max_penetration), f.get(SignalId::penetration));
  // trapezoids over accepted steps; the run's first step too, from t = 0, its end's values
  // held back over it (no frame at t = 0 is observed)
  const double h = first_step_ ? t : dt;
  if (first_step_) {
    force_prev_ = F;
    wear_prev_ = wear;
  }
  at(v_, MetricId::wear_integral) += 0.5 * (wear + wear_prev_) * h;
  if (F > 0.0 || force_prev_ > 0.0)
    at(v_, MetricId::contact_time) += (F > 0.0 && force_prev_ > 0.0) ? h : 0.5 * h;
  // contact episodes, from the latched impact speed / force
  const bool touching = f.get(SignalId::penetration) > 0.0;
  if (touching && !in_contact_ && ++episode_ == 1) first_episode_begins(f, t, ecc);
  if (!touching && in_contact_ && episode_ == 1) first_episode_ends(f, t);
  in_contact_ = touching;
  if (episode_ == 1 && touching)
    at(v_, MetricId::first_impact_peak_force) =
        std::max(at(v_, MetricId::first_impact_peak_force), F);
  if (episode_ >= 1 && t <= at(v_, MetricId::first_contact_time) + settings_.post_impact_window) {
    ecc_min_ = std::min(ecc_min_, ecc);
    ecc_max_ = std::max(ecc_max_, ecc);
  }
  force_prev_ = F;
  wear_prev_ = wear;
}

void MetricsAccumulator::first_episode_begins(const SignalFrame& f, double t, double ecc) {
  const double pen = f.get(SignalId::penetration);
  if (onsets_ == 0) {  // no onset reported (an observer fed frames only)
    at(v_, MetricId::first_contact_time) = t;
    at(v_, MetricId::first_impact_speed) = f.get(SignalId::impact_speed);
  }
  ecc_min_ = ecc;
  ecc_max_ = std::max(ecc, ecc_peak_pending_);
  // onset of the first episode for its duration: the driver's, else extrapolated back
  // along the approach from this first step end inside it (not before the previous one)
  if (onsets_ > 0) {
    first_onset_ = at(v_, MetricId::first_contact_time);
  } else {
    const double rate = f.get(SignalId::penetration_rate);
    first_onset_ = rate > 0.0 ? t - pen / rate : t;
    if (!first_step_) first_onset_ = std::max(first_onset_, t_prev_);
  }
  // dissipated energy at the last step end before the onset (0 at t = 0 by definition)
  dissipated_before_ = first_step_ ? 0.0 : dissipated_prev_;
}

void MetricsAccumulator::first_episode_ends(const SignalFrame& f, double t) {
  const double pen = f.get(SignalId::penetration);
  const double exit_rate = f.get(SignalId::penetration_rate);
  if (!(exit_rate < 0.0)) return;
  // the first episode ended during this step: this step end is the first after it. The
  // rate here is the exit speed delta'+ once the bodies fly freely (no force after the
  // end); the end is extrapolated back along it, not before the previous step end. (A
  // penetration that turns <= 0 while still approaching is no separation, but a body gone
  // through the centre of a failing run: the metrics of the episode then stay NaN.)
  const double approach = at(v_, MetricId::first_impact_speed);
  if (approach > 0.0) at(v_, MetricId::first_impact_restitution) = -exit_rate / approach;
  at(v_, MetricId::first_impact_duration) = std::max(t - pen / exit_rate, t_prev_) - first_onset_;
  if (has_energy_)
    at(v_, MetricId::first_impact_dissipated_energy) =
        f.get(SignalId::dissipated_energy) - dissipated_before_;
}

void MetricsAccumulator::step_surface(const SignalFrame& f, double t) {
  const double a = f.get(SignalId::surface_angle);
  at(v_, MetricId::final_surface_angle) = a;
  at(v_, MetricId::min_surface_angle) = std::isnan(at(v_, MetricId::min_surface_angle))
                                            ? a
                                            : std::min(at(v_, MetricId::min_surface_angle), a);
  at(v_, MetricId::max_surface_angle) = std::isnan(at(v_, MetricId::max_surface_angle))
                                            ? a
                                            : std::max(at(v_, MetricId::max_surface_angle), a);
  if (std::isnan(at(v_, MetricId::surface_motion_onset_time)) &&
      std::abs(a) > settings_.surface_motion_threshold)
    at(v_, MetricId::surface_motion_onset_time) = t;
}

void MetricsAccumulator::step_command(const SignalFrame& f) {
  // the end of each stroke: the last step end at which the command sits at its extreme (a
  // hold keeps it there exactly, so the last such step end is the end of the hold)
  const double c = f.get(command_signal_);
  const double err = f.get(SignalId::surface_angle_command) - f.get(SignalId::surface_angle);
  if (first_step_ || c >= command_max_) {
    command_max_ = first_step_ ? c : std::max(command_max_, c);
    at(v_, MetricId::surface_angle_error_extended) = err;
  }
  if (first_step_ || c <= command_min_) {
    command_min_ = first_step_ ? c : std::min(command_min_, c);
    at(v_, MetricId::surface_angle_error_retracted) = err;
  }
}

void MetricsAccumulator::step_chambers(const SignalFrame& f) {
  auto peak = [&](MetricId id, double p) {
    double& m = at(v_, id);
    m = std::isnan(m) ? p : std::max(m, p);
  };
  const double p1 = f.get(SignalId::chamber_pressures, 0);
  const double p2 = f.get(SignalId::chamber_pressures, 1);
  peak(MetricId::max_chamber_pressure, std::max(p1, p2));
  peak(MetricId::max_rear_chamber_pressure, p1);
  peak(MetricId::max_front_chamber_pressure, p2);
}

void MetricsAccumulator::step_crank(const SignalFrame& f, double t, double dt) {
  // revolutions counted from the first frame's crank angle; 1e-9 turn of slack so a run that
  // ends on a whole number of turns completes its last one despite round-off in the angle
  const double turn = 2.0 * std::numbers::pi;
  const double angle = f.get(SignalId::crank_angle);
  // the crank angle at t = 0: the first frame is the first step's end, so take back the
  // angle turned over that (short) step at the crank's rate there (exact at constant speed)
  if (first_step_)
    crank_start_ = angle - (has_crank_rate_ ? f.get(SignalId::surface_rate) * t : 0.0);
  const auto index =
      static_cast<long long>(std::floor(std::abs(angle - crank_start_) / turn + 1e-9));
  take_revolution(f, current_);  // the step that crosses a turn ends both revolutions
  take_rig(f, dt);
  if (index > revolution_) {
    close_rig_revolution();
    before_last_ = index == revolution_ + 1 ? last_ : Revolution{};
    last_ = index == revolution_ + 1 ? current_ : Revolution{};
    revolution_peaks_.push_back(current_.peak_acceleration);
    current_ = Revolution{};
    take_revolution(f, current_);
    revolution_ = index;
  }
}

void MetricsAccumulator::take_revolution(const SignalFrame& f, Revolution& r) const {
  r.peak_acceleration =
      std::max(r.peak_acceleration, std::abs(f.get(SignalId::slider_acceleration)));
  if (has_joint_forces_)
    for (int j = 0; j < 3; ++j)
      r.peak_force = std::max(r.peak_force, f.get(SignalId::joint_normal_forces, j));
  if (has_contact_) {
    const double e = f.get(SignalId::eccentricity);
    r.ecc_min = std::min(r.ecc_min, e);
    r.ecc_max = std::max(r.ecc_max, e);
  }
}

void MetricsAccumulator::step_energy(const SignalFrame& f) {
  const double w = f.get(SignalId::input_work);
  const double d = f.get(SignalId::dissipated_energy);
  const double r = f.get(SignalId::energy_residual);
  energy_scale_ =
      std::max(energy_scale_,
               energy_audit_scale(w, d, has_kinetic_ ? f.get(SignalId::kinetic_energy) : 0.0));
  max_residual_ = std::max(max_residual_, std::abs(r));
  at(v_, MetricId::input_work) = w;
  at(v_, MetricId::dissipated_energy) = d;
  dissipated_prev_ = d;
}

bool MetricsAccumulator::wants_peak(ContactPeak::Kind kind, double t0, double bound) const {
  if (!has_contact_) return false;
  // the first episode: the one under way, or the one a step before any contact may start
  const bool first_episode = episode_ == 0 || (episode_ == 1 && in_contact_);
  if (first_episode) return true;
  if (kind == ContactPeak::Kind::force) return bound > at(v_, MetricId::max_contact_force);
  // penetration: also the eccentricity's peak-to-peak within the post-impact window
  const double window_end = at(v_, MetricId::first_contact_time) + settings_.post_impact_window;
  return t0 <= window_end || bound > at(v_, MetricId::max_penetration);
}

void MetricsAccumulator::on_contact_peak(const ContactPeak& p) {
  const ContactSnapshot& c = p.at;
  if (!has_contact_ || !(c.penetration > 0.0)) return;
  double& F = at(v_, MetricId::max_contact_force);
  F = std::max(F, c.normal_force);
  double& pen = at(v_, MetricId::max_penetration);
  pen = std::max(pen, c.penetration);
  double& ecc = at(v_, MetricId::max_eccentricity);
  ecc = std::max(ecc, c.eccentricity);
  // the episode under way, or the one that this step starts (its step end comes next)
  const int episode = in_contact_ ? episode_ : episode_ + 1;
  if (episode == 1) {
    double& first = at(v_, MetricId::first_impact_peak_force);
    first = std::max(first, c.normal_force);
  }
  if (episode_ == 0 && episode == 1) {
    ecc_peak_pending_ = std::max(ecc_peak_pending_, c.eccentricity);
  } else if (episode_ >= 1 &&
             p.t <= at(v_, MetricId::first_contact_time) + settings_.post_impact_window) {
    ecc_min_ = std::min(ecc_min_, c.eccentricity);
    ecc_max_ = std::max(ecc_max_, c.eccentricity);
  }
}

void MetricsAccumulator::on_contact_onset(double t, double impact_speed) {
  onset_times_.push_back(t);
  if (pressure_hf_) pressure_hf_->onset(t);
  if (has_contact_ && onsets_++ == 0) {
    at(v_, MetricId::first_contact_time) = t;
    at(v_, MetricId::first_impact_speed) = impact_speed;
  }
}

SettledPeak settled_peak(std::span<const double> pk) {
  SettledPeak out;
  // the window of a run cut after m revolutions: revolutions m/2 .. m-1 (0-based)
  auto window = [&](std::size_t m) { return pk.subspan(m / 2, m - m / 2); };
  auto peak_of = [&](std::size_t m) {
    const auto w = window(m);
    return *std::max_element(w.begin(), w.end());
  };
  const std::size_t n = pk.size();
  if (n < 2) return out;
  out.peak = peak_of(n);
  std::vector<double> w(window(n).begin(), window(n).end());
  std::sort(w.begin(), w.end());
  out.median = w.size() % 2 ? w[w.size() / 2] : 0.5 * (w[w.size() / 2 - 1] + w[w.size() / 2]);
  const auto back = static_cast<std::size_t>(kSettleRevolutions);
  if (n < back + 2 || !(out.peak > 0.0)) return out;
  out.change = 0.0;
  for (std::size_t k = 1; k <= back; ++k)
    out.change = std::max(out.change, std::abs(peak_of(n - k) - out.peak) / out.peak);
  // the two halves of the window, disjoint: an early spike in every cut window above is in
  // one half only (issue 36)
  const auto full = window(n);
  const auto half = full.size() / 2;
  const double first = *std::max_element(full.begin(), full.begin() + half);
  const double second = *std::max_element(full.begin() + half, full.end());
  out.change = std::max(out.change, std::abs(first - second) / out.peak);
  return out;
}

ButterworthLowPass::ButterworthLowPass(double cutoff_hz, int order)
    : omega_(2.0 * std::numbers::pi * cutoff_hz) {
  // poles omega exp(i pi (2k + n + 1) / (2n)), k = 0 .. n-1: the pairs k, n-1-k have damping
  // sin(pi (2k + 1) / (2n)); the real pole of an odd order is a first-order section
  for (int k = 0; k < order / 2; ++k)
    sections_.push_back({std::sin(std::numbers::pi * (2 * k + 1) / (2.0 * order))});
  if (order % 2) sections_.push_back({-1.0});
}

double ButterworthLowPass::reset(double u) {
  for (Section& s : sections_) {
    s.x0 = u;
    s.x1 = 0.0;
  }
  u_prev_ = u;
  return u;
}

namespace {

/// A 2x2 matrix [a b; c d].
struct Mat2 {
  double a = 0, b = 0, c = 0, d = 0;
};
Mat2 mul(const Mat2& x, const Mat2& y) {
  return {x.a * y.a + x.b * y.c, x.a * y.b + x.b * y.d, x.c * y.a + x.d * y.c,
          x.c * y.b + x.d * y.d};
}
/// x + k y
Mat2 add(const Mat2& x, const Mat2& y, double k) {
  return {x.a + k * y.a, x.b + k * y.b, x.c + k * y.c, x.d + k * y.d};
}

/// The exact step of x' = A x + b u over h with u linear from u0 to u1:
/// x(h) = Phi x0 + G0 b u0 + G1 b (u1 - u0) / h, Phi = e^{A h}, G0 = int_0^h e^{A s} ds,
/// G1 = int_0^h e^{A s} (h - s) ds. For |A| h < 0.05 by their series (ten terms: truncation
/// below 1e-15 relative), else in closed form, G0 = A^-1 (Phi - I), G1 = A^-1 (G0 - h I).
struct Discrete {
  Mat2 phi, g0, g1;
};
Discrete discretise(const Mat2& A, const Mat2& phi, double h, bool small) {
  const Mat2 I{1, 0, 0, 1};
  Discrete r;
  if (!small) {
    const double det = A.a * A.d - A.b * A.c;
    const Mat2 inv{A.d / det, -A.b / det, -A.c / det, A.a / det};
    r.phi = phi;
    r.g0 = mul(inv, add(phi, I, -1.0));
    r.g1 = mul(inv, add(r.g0, I, -h));
    return r;
  }
  // Phi = sum (A h)^k / k!, G0 = h sum (A h)^k / (k+1)!, G1 = h^2 sum (A h)^k / (k+2)!
  Mat2 power = I;     // (A h)^k
  double fact = 1.0;  // k!
  for (int k = 0; k < 10; ++k) {
    if (k > 0) {
      power = add(Mat2{}, mul(power, A), h);
      fact *= k;
    }
    r.phi = add(r.phi, power, 1.0 / fact);
    r.g0 = add(r.g0, power, h / (fact * (k + 1)));
    r.g1 = add(r.g1, power, h * h / (fact * (k + 1) * (k + 2)));
  }
  return r;
}

}  // namespace

double ButterworthLowPass::step(double h, double u) {
  double in0 = u_prev_, in1 = u;
  u_prev_ = u;  // each section's input: the previous section's output
  for (Section& s : sections_) {
    const double y0 = s.x0;
    if (!(h > 0.0)) {
      // a repeated sample: no time passes
    } else if (s.zeta < 0.0) {
      // first order, y' = w (u - y): Phi = e^{-w h}, G0 b = 1 - Phi, G1 b = h - (1 - Phi) / w
      const double one_minus_phi = -std::expm1(-omega_ * h);
      const double k = (in1 - in0) / h;
      s.x0 = (1.0 - one_minus_phi) * s.x0 + one_minus_phi * in0 + (h - one_minus_phi / omega_) * k;
    } else {
      // second order, x = (y, y'), y'' + 2 zeta w y' + w^2 y = w^2 u, b = (0, w^2)
      const double w = omega_, sigma = s.zeta * w, wd = w * std::sqrt(1.0 - s.zeta * s.zeta);
      const Mat2 A{0.0, 1.0, -w * w, -2.0 * sigma};
      const double e = std::exp(-sigma * h), sn = std::sin(wd * h) / wd;
      const Mat2 phi{e * (std::cos(wd * h) + sn * sigma), e * sn, e * sn * A.c,
                     e * (std::cos(wd * h) + sn * (A.d + sigma))};
      const Discrete dz = discretise(A, phi, h, w * h < 0.05);
      const double k = (in1 - in0) / h, b = w * w;
      const double x0 = s.x0, x1 = s.x1;
      s.x0 = dz.phi.a * x0 + dz.phi.b * x1 + dz.g0.b * b * in0 + dz.g1.b * b * k;
      s.x1 = dz.phi.c * x0 + dz.phi.d * x1 + dz.g0.d * b * in0 + dz.g1.d * b * k;
    }
    in0 = y0;
    in1 = s.x0;
  }
  return in1;
}

double percentile(std::vector<double> values, double q) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

RigMetrics rig_metrics(std::span<const RigRevolution> revs) {
  RigMetrics out;
  const std::size_t n = revs.size();
  if (n < 2) return out;
  const auto window = revs.subspan(n / 2);  // N/2+1 .. N, as settled_peak()
  std::vector<double> peaks, filtered;
  double lo = kNaN, hi = kNaN, flo = kNaN, fhi = kNaN, ecc = kNaN;
  for (const RigRevolution& r : window) {
    peaks.push_back(r.peak);
    filtered.push_back(r.filtered_peak);
    lo = std::isnan(lo) ? r.min : std::min(lo, r.min);
    hi = std::isnan(hi) ? r.max : std::max(hi, r.max);
    flo = std::isnan(flo) ? r.filtered_min : std::min(flo, r.filtered_min);
    fhi = std::isnan(fhi) ? r.filtered_max : std::max(fhi, r.filtered_max);
    ecc = std::isnan(ecc) ? r.min_ecc_ratio : std::min(ecc, r.min_ecc_ratio);
  }
  out.median = percentile(peaks, 0.5);
  out.p95 = percentile(peaks, 0.95);
  out.ptp = hi - lo;
  out.filtered_median = percentile(filtered, 0.5);
  out.filtered_p95 = percentile(filtered, 0.95);
  out.filtered_ptp = fhi - flo;
  out.filtered_peak = *std::max_element(filtered.begin(), filtered.end());
  out.min_ecc_ratio = ecc;
  return out;
}

namespace {
/// `r` extended by one more sample's record `f`.
void merge(RigRevolution& r, const RigRevolution& f) {
  r.peak = std::max(r.peak, f.peak);
  r.min = std::min(r.min, f.min);
  r.max = std::max(r.max, f.max);
  r.filtered_peak = std::max(r.filtered_peak, f.filtered_peak);
  r.filtered_min = std::min(r.filtered_min, f.filtered_min);
  r.filtered_max = std::max(r.filtered_max, f.filtered_max);
  r.min_ecc_ratio = std::min(r.min_ecc_ratio, f.min_ecc_ratio);
}
}  // namespace

void MetricsAccumulator::take_rig(const SignalFrame& f, double dt) {
  const double a = f.get(SignalId::slider_acceleration);
  RigRevolution& r = rig_frame_;
  r = RigRevolution{};
  r.peak = std::abs(a);
  r.min = r.max = a;
  if (lowpass_) {
    const double y = lowpass_started_ ? lowpass_->step(dt, a) : lowpass_->reset(a);
    lowpass_started_ = true;
    r.filtered_peak = std::abs(y);
    r.filtered_min = r.filtered_max = y;
  } else {
    r.filtered_peak = r.filtered_min = r.filtered_max = kNaN;
  }
  if (has_contact_) {
    // the clearance is |e| - penetration (the penetration is |e| - c, signed)
    const double e = f.get(SignalId::eccentricity);
    const double c = e - f.get(SignalId::penetration);
    if (c > 0.0) r.min_ecc_ratio = e / c;
  }
  merge(rig_current_, r);
}

void MetricsAccumulator::close_rig_revolution() {
  rig_revolutions_.push_back(rig_current_);
  rig_current_ = rig_frame_;  // the step that crosses a turn ends both revolutions
}

void MetricsAccumulator::finish_rig(MetricValues& v) const {
  const RigMetrics m = rig_metrics(rig_revolutions_);
  at(v, MetricId::p95_revolution_peak_slider_acceleration) = m.p95;
  at(v, MetricId::slider_acceleration_peak_to_peak) = m.ptp;
  if (lowpass_) {
    at(v, MetricId::lowpass_median_revolution_peak_slider_acceleration) = m.filtered_median;
    at(v, MetricId::lowpass_p95_revolution_peak_slider_acceleration) = m.filtered_p95;
    at(v, MetricId::lowpass_peak_slider_acceleration_settled) = m.filtered_peak;
    at(v, MetricId::lowpass_slider_acceleration_peak_to_peak) = m.filtered_ptp;
  }
  if (has_contact_ && std::isfinite(m.min_ecc_ratio))
    at(v, MetricId::steady_min_eccentricity_ratio) = m.min_ecc_ratio;
}

MetricValues MetricsAccumulator::finish(const RunStats& stats) const {
  MetricValues v = v_;
  if (has_contact_) {
    at(v, MetricId::impact_count) = static_cast<double>(stats.contact_onsets);
    if (episode_ >= 1) at(v, MetricId::eccentricity_ptp_after_first_contact) = ecc_max_ - ecc_min_;
    if (std::isinf(at(v, MetricId::max_penetration))) at(v, MetricId::max_penetration) = kNaN;
  }
  if (has_energy_)
    at(v, MetricId::energy_residual) = energy_scale_ > 0.0 ? max_residual_ / energy_scale_ : 0.0;
  if (has_crank_) {
    at(v, MetricId::revolutions) = static_cast<double>(revolution_);
    if (revolution_ >= 1) finish_crank(v);
  }
  if (periodic_.active()) finish_periodic(v);
  if (linkage_.active()) {
    const LinkageMetrics l = linkage_.finish();
    at(v, MetricId::surface_angle_error_percent) = l.angle_error_percent;
    at(v, MetricId::surface_rate_fluctuation) = l.rate_fluctuation;
    at(v, MetricId::surface_acceleration_fluctuation) = l.acceleration_fluctuation;
    at(v, MetricId::main_frequency) = l.main_frequency;
    at(v, MetricId::main_frequency_amplitude) = l.main_frequency_amplitude;
  }
  finish_features(v);
  at(v, MetricId::max_penetration_fraction) = stats.max_penetration_fraction;
  at(v, MetricId::max_penetration_strain) = stats.max_penetration_strain;
  at(v, MetricId::max_quaternion_norm_error) = stats.max_quaternion_norm_error;
  return v;
}

void MetricsAccumulator::finish_crank(MetricValues& v) const {
  const double peak = last_.peak_acceleration;
  at(v, MetricId::peak_slider_acceleration) = peak;
  if (revolution_ >= 2 && peak > 0.0)
    at(v, MetricId::peak_slider_acceleration_change) =
        std::abs(peak - before_last_.peak_acceleration) / peak;
  // the period of the settled response: the last p turns repeat the p before them
  const std::vector<double>& pk = revolution_peaks_;
  const std::size_t n = pk.size();
  for (std::size_t period = 1; period <= 4 && 2 * period <= n; ++period) {
    bool repeats = true;
    double cycle = 0.0;
    for (std::size_t j = 0; j < period; ++j) {
      const double now = pk[n - 1 - j], before = pk[n - 1 - j - period];
      repeats = repeats && std::abs(now - before) <= 0.01 * now;
      cycle = std::max(cycle, now);
    }
    if (repeats) {
      at(v, MetricId::steady_cycle_revolutions) = static_cast<double>(period);
      at(v, MetricId::peak_slider_acceleration_cycle) = cycle;
      break;
    }
  }
  const SettledPeak settled = settled_peak(revolution_peaks_);
  at(v, MetricId::peak_slider_acceleration_settled) = settled.peak;
  at(v, MetricId::median_revolution_peak_slider_acceleration) = settled.median;
  at(v, MetricId::peak_slider_acceleration_settled_change) = settled.change;
  if (!std::isnan(settled.change))
    at(v, MetricId::slider_response_settled) = settled.change < 0.01 ? 1.0 : 0.0;
  finish_rig(v);
  if (has_contact_) {
    if (has_joint_forces_) at(v, MetricId::peak_contact_force) = last_.peak_force;
    at(v, MetricId::last_revolution_min_eccentricity) = last_.ecc_min;
    at(v, MetricId::last_revolution_max_eccentricity) = last_.ecc_max;
  }
}

void MetricsAccumulator::finish_periodic(MetricValues& v) const {
  const PeriodicMetrics p = periodic_.finish();
  at(v, MetricId::drive_frequency) = p.drive_frequency;
  at(v, MetricId::piston_gain) = p.piston_gain;
  at(v, MetricId::piston_phase) = p.piston_phase;
  at(v, MetricId::surface_gain) = p.surface_gain;
  at(v, MetricId::surface_phase) = p.surface_phase;
  at(v, MetricId::response_settling) = p.response_settling;
  at(v, MetricId::free_play) = p.free_play;
  at(v, MetricId::stiffness_positive) = p.stiffness_positive;
  at(v, MetricId::stiffness_negative) = p.stiffness_negative;
  at(v, MetricId::hysteresis) = p.hysteresis;
}

}  // namespace rodend
