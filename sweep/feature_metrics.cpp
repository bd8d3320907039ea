#include "sweep/feature_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sweep/metrics.hpp"

namespace rodend {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

HighPassFeature::HighPassFeature(double cutoff_hz, double window)
    : low_(2, cutoff_hz), window_(window) {}

void HighPassFeature::close_windows(double t) {
  // windows that end before t are done (the peak read at the points inside them)
  std::size_t keep = 0;
  for (std::size_t i = 0; i < open_.size(); ++i) {
    if (open_[i] + window_ < t) {
      peak_sum_ += open_peak_[i];
      ++closed_;
    } else {
      open_[keep] = open_[i];
      open_peak_[keep++] = open_peak_[i];
    }
  }
  open_.resize(keep);
  open_peak_.resize(keep);
}

void HighPassFeature::add(double t, double u) {
  if (!started_) {
    low_.reset(u);  // at rest: the high-passed value starts at 0
    started_ = true;
    t0_ = t_ = t, u_ = u, hp_ = 0.0;
    return;
  }
  if (!(t > t_)) return;
  low_.advance(t - t_, u_, (u - u_) / (t - t_));
  const double hp = u - low_.output();
  integral_ += 0.5 * (hp * hp + hp_ * hp_) * (t - t_);  // trapezoids
  close_windows(t);
  for (std::size_t i = 0; i < open_.size(); ++i)
    open_peak_[i] = std::max(open_peak_[i], std::abs(hp));
  t_ = t, u_ = u, hp_ = hp;
}

void HighPassFeature::onset(double t) {
  open_.push_back(t);
  open_peak_.push_back(0.0);
}

double HighPassFeature::mean_square() const {
  return t_ > t0_ ? integral_ / (t_ - t0_) : kNaN;
}

double HighPassFeature::onset_peak_mean() const {
  // a window that ended between the last two points is complete: count it too
  double sum = peak_sum_;
  int n = closed_;
  for (std::size_t i = 0; i < open_.size(); ++i)
    if (open_[i] + window_ <= t_) sum += open_peak_[i], ++n;
  return n > 0 ? sum / n : kNaN;
}

void replay(HighPassFeature& f, const std::vector<double>& times, const std::vector<double>& values,
            const std::vector<double>& onsets) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < times.size(); ++i) {
    // an onset between the previous point and this one opens its window before this point
    for (; k < onsets.size() && onsets[k] <= times[i]; ++k)
      if (i > 0) f.onset(onsets[k]);
    f.add(times[i], values[i]);
  }
}

namespace {

/// The first sensor on `signal` (component `component`), or null.
const SensorChannel* sensor_on(const std::vector<SensorChannel>& sensors, SignalId signal,
                               int component = 0) {
  for (const SensorChannel& s : sensors)
    if (s.signal() == signal && s.spec().component == component) return &s;
  return nullptr;
}

}  // namespace

void MetricsAccumulator::finish_features(MetricValues& v) const {
  if (accel_hf_) metric(v, MetricId::surface_acceleration_hf) = accel_hf_->mean_square();
  if (pressure_hf_) metric(v, MetricId::pressure_ripple) = pressure_hf_->onset_peak_mean();
  // onsets per period over the drive's whole periods after the first
  const std::optional<PeriodicInput> in = periodic_.drive();
  if (!has_contact_ || !in || first_step_) return;
  const double T = 1.0 / in->frequency;
  const int whole =
      std::min(in->cycles, static_cast<int>(std::floor((t_prev_ - in->start_time) / T)));
  if (whole < 2) return;
  const double from = in->start_time + T, to = in->start_time + whole * T;
  const auto n = std::count_if(onset_times_.begin(), onset_times_.end(),
                               [&](double t) { return t >= from && t < to; });
  metric(v, MetricId::contact_onsets_per_cycle) = static_cast<double>(n) / (whole - 1);
}

void MetricsAccumulator::finish_sensed(const std::vector<SensorChannel>& sensors,
                                       MetricValues& v) const {
  if (const SensorChannel* a = sensor_on(sensors, SignalId::surface_acceleration); a && accel_hf_) {
    HighPassFeature f(settings_.feature_highpass, settings_.onset_window);
    replay(f, a->times(), a->values(), {});
    metric(v, MetricId::sensed_surface_acceleration_hf) = f.mean_square();
  }
  if (const SensorChannel* p = sensor_on(sensors, SignalId::chamber_pressures); p && pressure_hf_) {
    HighPassFeature f(settings_.feature_highpass, settings_.onset_window);
    replay(f, p->times(), p->values(), onset_times_);
    metric(v, MetricId::sensed_pressure_ripple) = f.onset_peak_mean();
  }
  const SensorChannel* angle = sensor_on(sensors, SignalId::surface_angle);
  const SensorChannel* accel = sensor_on(sensors, SignalId::surface_acceleration);
  if (const std::optional<PeriodicInput> in = periodic_.drive(); in && (angle || accel)) {
    const double w = 2.0 * std::numbers::pi * in->frequency;
    const SensorChannel& s = angle ? *angle : *accel;
    const auto [gain, phase] =
        periodic_.sensed_response(s.times(), s.values(), angle ? 1.0 : -1.0 / (w * w));
    metric(v, MetricId::sensed_surface_gain) = gain;
    metric(v, MetricId::sensed_surface_phase) = phase;
  }
  const SensorChannel* moment = sensor_on(sensors, SignalId::hinge_moment);
  if (angle && moment && angle->times() == moment->times()) {
    const auto [loop, play] =
        periodic_.sensed_loop(angle->times(), moment->values(), angle->values());
    metric(v, MetricId::sensed_hysteresis) = loop;
    metric(v, MetricId::sensed_free_play) = play;
  }
}

}  // namespace rodend
