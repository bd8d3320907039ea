#include "core/scenes/input_waveforms.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "core/scenes/parts.hpp"

namespace rodend {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// tri(phase): 0 -> 1 -> -1 -> 0 in straight lines over one period, and its slope.
void triangle(double phase, double& w, double& dw) {
  const double u = phase - std::floor(phase);
  if (u < 0.25) {
    w = 4.0 * u, dw = 4.0;
  } else if (u < 0.75) {
    w = 2.0 - 4.0 * u, dw = -4.0;
  } else {
    w = 4.0 * u - 4.0, dw = 4.0;
  }
}

}  // namespace

WaveformLevel read_waveform_level(const InputKeys& in) {
  WaveformLevel l;
  if (!in.unit) {
    l.amplitude = in.positive("amplitude", true);
    l.offset = in.number("offset");
    if (!std::isfinite(l.offset)) throw InputError(in.key("offset"), "expected a finite value");
  }
  l.start_time = in.positive("start_time", true);
  return l;
}

WavePeriods read_wave_periods(const InputKeys& in) {
  return {in.positive("frequency"), in.cycles("cycles")};
}

ChirpSweep read_chirp_sweep(const InputKeys& in) {
  ChirpSweep c;
  c.start_frequency = in.positive("start_frequency");
  c.end_frequency = in.positive("end_frequency");
  c.duration = in.positive("chirp_duration");
  if (c.end_frequency < c.start_frequency)
    throw InputError(in.key("end_frequency"),
                     "the chirp's end frequency " + format_number(c.end_frequency) +
                         " Hz precedes its start frequency " + format_number(c.start_frequency) +
                         " Hz: a chirp sweeps upwards (start_frequency <= end_frequency)");
  return c;
}

Input::Sample Waveform::at(double t) const {
  const double tau = t - l_.start_time;
  if (tau < 0.0) return {l_.offset, 0.0, 0.0};
  // after the window: the end value (offset after whole periods; a chirp holds where it ended)
  if (t > end_time()) return {ends_at_offset() ? l_.offset : at(end_time()).value, 0.0, 0.0};
  return inside(tau);
}

std::pair<double, double> Waveform::range() const {
  return {l_.offset - l_.amplitude, l_.offset + l_.amplitude};
}

Input::Sample Waveform::sinusoid(double phase, double f, double df) const {
  const double A = l_.amplitude;
  const double s = std::sin(kTwoPi * phase), c = std::cos(kTwoPi * phase);
  return {l_.offset + A * s, A * kTwoPi * f * c,
          A * (kTwoPi * df * c - kTwoPi * kTwoPi * f * f * s)};
}

InputPtr SineWave::read(const InputKeys& in) {
  const WaveformLevel l = read_waveform_level(in);
  return std::make_shared<SineWave>(l, read_wave_periods(in));
}

Input::Sample SineWave::inside(double tau) const {
  return sinusoid(periods().frequency * tau, periods().frequency, 0.0);
}

double SineWave::integral(double t) const {
  // offset t + A (1 - cos(2 pi f tau))/(2 pi f) over the window, offset outside it
  const double t0 = level().start_time, t1 = std::clamp(t, t0, end_time());
  const double w = kTwoPi * periods().frequency;
  return level().offset * t + level().amplitude * (1.0 - std::cos(w * (t1 - t0))) / w;
}

InputPtr TriangleWave::read(const InputKeys& in) {
  const WaveformLevel l = read_waveform_level(in);
  return std::make_shared<TriangleWave>(l, read_wave_periods(in));
}

Input::Sample TriangleWave::inside(double tau) const {
  double w, dw;
  triangle(periods().frequency * tau, w, dw);
  return {level().offset + level().amplitude * w, level().amplitude * dw * periods().frequency,
          0.0};
}

InputPtr LinearChirp::read(const InputKeys& in) {
  const WaveformLevel l = read_waveform_level(in);
  return std::make_shared<LinearChirp>(l, read_chirp_sweep(in));
}

Input::Sample LinearChirp::inside(double tau) const {
  const ChirpSweep& c = sweep();
  const double df = (c.end_frequency - c.start_frequency) / c.duration;
  return sinusoid(c.start_frequency * tau + 0.5 * df * tau * tau, c.start_frequency + df * tau, df);
}

LogChirp::LogChirp(const WaveformLevel& l, const ChirpSweep& c)
    : Chirp(l, c), log_ratio_(std::log(c.end_frequency / c.start_frequency)) {}

InputPtr LogChirp::read(const InputKeys& in) {
  const WaveformLevel l = read_waveform_level(in);
  return std::make_shared<LogChirp>(l, read_chirp_sweep(in));
}

Input::Sample LogChirp::inside(double tau) const {
  const ChirpSweep& c = sweep();
  const double lk = log_ratio_;
  const double g = std::exp(lk * tau / c.duration);  // k^(tau/D)
  const double f = c.start_frequency * g;
  const double phase =
      lk > 0.0 ? c.start_frequency * c.duration * (g - 1.0) / lk : c.start_frequency * tau;
  return sinusoid(phase, f, f * lk / c.duration);
}

}  // namespace rodend
