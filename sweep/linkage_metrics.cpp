#include "sweep/linkage_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rodend {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool provides(const Scene& s, SignalId id) {
  const auto sig = s.signals();
  return std::find(sig.begin(), sig.end(), id) != sig.end();
}

}  // namespace

LinkageMetricsAccumulator::LinkageMetricsAccumulator(const Scene& scene) {
  const std::optional<PeriodicInput> in = scene.periodic_inputs().command;
  if (!in || !provides(scene, SignalId::ideal_surface_acceleration) ||
      !provides(scene, SignalId::surface_angle_command))
    return;
  input_ = in;
  for (int h = 1; h <= kHarmonics; ++h) {
    PeriodicInput p = *in;
    p.frequency = h * in->frequency;
    p.cycles = h * in->cycles;
    harmonics_.emplace_back(p, 1, h);  // the last h harmonic periods: one command period
  }
}

void LinkageMetricsAccumulator::on_step(const SignalFrame& f) {
  const double t = f.get(SignalId::time);
  const double a = f.get(SignalId::surface_acceleration);
  for (PeriodSamples& s : harmonics_) s.add(t, std::span<const double>(&a, 1));
  if (t < input_->start_time + 1.0 / input_->frequency) return;  // the first period
  const double ideal = f.get(SignalId::surface_angle_command);
  angle_error_ = std::max(angle_error_, std::abs(f.get(SignalId::surface_angle) - ideal));
  rate_error_ = std::max(
      rate_error_, std::abs(f.get(SignalId::surface_rate) - f.get(SignalId::ideal_surface_rate)));
  acceleration_error_ =
      std::max(acceleration_error_, std::abs(a - f.get(SignalId::ideal_surface_acceleration)));
  ideal_min_ = seen_ ? std::min(ideal_min_, ideal) : ideal;
  ideal_max_ = seen_ ? std::max(ideal_max_, ideal) : ideal;
  seen_ = true;
}

LinkageMetrics LinkageMetricsAccumulator::finish() const {
  LinkageMetrics m{kNaN, kNaN, kNaN, kNaN, kNaN};
  if (!seen_) return m;
  const double amplitude = 0.5 * (ideal_max_ - ideal_min_);
  m.angle_error_percent = amplitude > 0.0 ? 100.0 * angle_error_ / amplitude : kNaN;
  m.rate_fluctuation = rate_error_;
  m.acceleration_fluctuation = acceleration_error_;
  // the last whole command period, if it is not the first
  const int periods = harmonics_.front().completed();
  if (periods < 2) return m;
  const double T = 1.0 / input_->frequency;
  double best = -1.0;
  for (int h = 1; h <= kHarmonics; ++h) {
    const PeriodSamples& s = harmonics_[static_cast<std::size_t>(h - 1)];
    std::complex<double> sum = 0.0;
    // its own last h periods: one command period T (ending at most one harmonic period apart)
    for (int k = s.completed() - h; k < s.completed(); ++k) sum += s.fourier(k, 0);
    const double amp = 2.0 * std::abs(sum) / T;
    if (amp > best) {
      best = amp;
      m.main_frequency = h * input_->frequency;
      m.main_frequency_amplitude = amp;
    }
  }
  return m;
}

}  // namespace rodend
