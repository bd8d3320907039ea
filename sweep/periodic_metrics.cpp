#include "sweep/periodic_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace rodend {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kTwoPi = 2.0 * std::numbers::pi;

template <class T>
bool provides(const Scene& s, T id) {
  const auto sig = s.signals();
  return std::find(sig.begin(), sig.end(), id) != sig.end();
}

/// Integral over [a, b] of (ya + (yb - ya)(t - a)/(b - a)) exp(-i w t) dt: exact, or the
/// trapezoid when w (b - a) < 1e-2 (then within (w h)^2/12 < 1e-5 of it; the exact form would
/// cancel digits).
std::complex<double> linear_times_phasor(double a, double b, double ya, double yb, double w) {
  const double h = b - a;
  const std::complex<double> ea = std::polar(1.0, -w * a), eb = std::polar(1.0, -w * b);
  if (w * h < 1e-2) return 0.5 * h * (ya * ea + yb * eb);
  const std::complex<double> iw(0.0, -w);  // d/dt exp(-i w t) = -i w exp(-i w t)
  // int (t - a) E dt = h E(b)/(-i w) - (E(b) - E(a))/(-i w)^2
  const std::complex<double> ramp = h * eb / iw - (eb - ea) / (iw * iw);
  return ya * (eb - ea) / iw + (yb - ya) / h * ramp;
}

}  // namespace

PeriodSamples::PeriodSamples(const PeriodicInput& in, int channels, int keep_periods)
    : in_(in), channels_(channels), keep_(keep_periods) {}

void PeriodSamples::add(double t, std::span<const double> values) {
  const double T = 1.0 / in_.frequency;
  const double end = in_.start_time + in_.cycles * T;
  const std::size_t w = static_cast<std::size_t>(channels_) + 1;
  // past the window: one sample beyond its end is enough to interpolate the end
  if (!rows_.empty() && rows_[rows_.size() - w] >= end) return;
  rows_.push_back(t);
  rows_.insert(rows_.end(), values.begin(), values.begin() + channels_);
  completed_ = std::clamp(static_cast<int>(std::floor((t - in_.start_time) / T)), 0, in_.cycles);
  // drop the samples before the first period kept, less one (to interpolate its start), once
  // they are half the buffer
  const double keep_from = in_.start_time + (completed_ - keep_) * T;
  while ((stale_ + 2) * w <= rows_.size() && rows_[(stale_ + 1) * w] <= keep_from) ++stale_;
  if (stale_ * w * 2 > rows_.size()) {
    rows_.erase(rows_.begin(), rows_.begin() + static_cast<std::ptrdiff_t>(stale_ * w));
    stale_ = 0;
  }
}

std::vector<double> PeriodSamples::period_rows(int k) const {
  const double T = 1.0 / in_.frequency;
  const double a = in_.start_time + k * T, b = a + T;
  const std::size_t w = static_cast<std::size_t>(channels_) + 1, n = rows_.size() / w;
  std::vector<double> out;
  auto interpolate = [&](std::size_t i, double t) {  // between rows i and i + 1
    const double t0 = rows_[i * w], t1 = rows_[(i + 1) * w];
    const double s = t1 > t0 ? (t - t0) / (t1 - t0) : 0.0;
    out.push_back(t);
    for (std::size_t c = 1; c < w; ++c)
      out.push_back(rows_[i * w + c] + s * (rows_[(i + 1) * w + c] - rows_[i * w + c]));
  };
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double t0 = rows_[i * w], t1 = rows_[(i + 1) * w];
    if (t1 <= a || t0 >= b) continue;
    if (out.empty()) interpolate(i, std::max(a, t0));
    if (t1 < b) {
      out.insert(out.end(), rows_.begin() + static_cast<std::ptrdiff_t>((i + 1) * w),
                 rows_.begin() + static_cast<std::ptrdiff_t>((i + 2) * w));
    } else {
      interpolate(i, b);
    }
  }
  return out;
}

std::complex<double> PeriodSamples::fourier(int k, int c) const {
  const std::vector<double> r = period_rows(k);
  const std::size_t w = static_cast<std::size_t>(channels_) + 1, n = r.size() / w;
  const double omega = kTwoPi * in_.frequency;
  std::complex<double> sum = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i)
    sum += linear_times_phasor(r[i * w] - in_.start_time, r[(i + 1) * w] - in_.start_time,
                               r[i * w + 1 + c], r[(i + 1) * w + 1 + c], omega);
  return sum;
}

double PeriodSamples::loop_area(int k, int x, int y) const {
  const std::vector<double> r = period_rows(k);
  const std::size_t w = static_cast<std::size_t>(channels_) + 1, n = r.size() / w;
  double area = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i)
    area += 0.5 * (r[i * w + 1 + y] + r[(i + 1) * w + 1 + y]) *
            (r[(i + 1) * w + 1 + x] - r[i * w + 1 + x]);
  return area;
}

std::pair<double, double> PeriodSamples::fit(int k, int x, int y, double lo, double hi) const {
  // least squares in time over the piecewise-linear interpolant: each segment clipped to the
  // part where channel x lies in [lo, hi], its moments (1, X, Y, X^2, XY: at most quadratic in
  // time) integrated exactly by Simpson's rule
  const std::vector<double> r = period_rows(k);
  const std::size_t w = static_cast<std::size_t>(channels_) + 1, n = r.size() / w;
  double m[5] = {0, 0, 0, 0, 0};
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double t0 = r[i * w], t1 = r[(i + 1) * w];
    const double X0 = r[i * w + 1 + x], X1 = r[(i + 1) * w + 1 + x];
    const double Y0 = r[i * w + 1 + y], Y1 = r[(i + 1) * w + 1 + y];
    double ua = 0.0, ub = 1.0;
    if (X1 != X0) {
      const double u_lo = (lo - X0) / (X1 - X0), u_hi = (hi - X0) / (X1 - X0);
      ua = std::max(0.0, std::min(u_lo, u_hi)), ub = std::min(1.0, std::max(u_lo, u_hi));
    } else if (X0 < lo || X0 > hi) {
      continue;
    }
    if (!(ub > ua)) continue;
    const double dt = (t1 - t0) * (ub - ua);
    for (const auto& [u, weight] : {std::pair{ua, 1.0}, {0.5 * (ua + ub), 4.0}, {ub, 1.0}}) {
      const double X = X0 + u * (X1 - X0), Y = Y0 + u * (Y1 - Y0), c = weight * dt / 6.0;
      m[0] += c, m[1] += c * X, m[2] += c * Y, m[3] += c * X * X, m[4] += c * X * Y;
    }
  }
  const double det = m[0] * m[3] - m[1] * m[1];
  if (!(det > 1e-12 * m[0] * m[3])) return {kNaN, kNaN};
  const double b = (m[0] * m[4] - m[1] * m[2]) / det;
  return {(m[2] - b * m[1]) / m[0], b};
}

// command channels: 0 command, 1 surface angle command, 2 piston, 3 surface angle
// load channels: 0 hinge moment, 1 surface angle
PeriodicAccumulator::PeriodicAccumulator(const Scene& scene) {
  const PeriodicInputs in = scene.periodic_inputs();
  has_surface_ = provides(scene, SignalId::surface_angle);
  has_piston_ = provides(scene, SignalId::actuator_command);
  // the command: the actuator's, else the prescribed rod motion (rod-end-kinematic)
  command_signal_ = has_piston_ ? SignalId::actuator_command : SignalId::actuator_position;
  if (in.command && provides(scene, command_signal_)) {
    command_in_ = *in.command;
    command_.emplace(command_in_, 4, 3);
  }
  if (in.load && has_surface_ && provides(scene, SignalId::hinge_moment)) {
    load_in_ = *in.load;
    load_.emplace(load_in_, 2, 2);
  }
}

void PeriodicAccumulator::on_step(const SignalFrame& f) {
  const double t = f.get(SignalId::time);
  if (command_) {
    const double v[4] = {f.get(command_signal_),
                         has_surface_ ? f.get(SignalId::surface_angle_command) : 0.0,
                         has_piston_ ? f.get(SignalId::actuator_position) : 0.0,
                         has_surface_ ? f.get(SignalId::surface_angle) : 0.0};
    command_->add(t, v);
  }
  if (load_) {
    const double v[2] = {f.get(SignalId::hinge_moment), f.get(SignalId::surface_angle)};
    load_->add(t, v);
  }
}

PeriodicMetrics PeriodicAccumulator::finish() const {
  PeriodicMetrics m{kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN, kNaN};
  if (command_) {
    m.drive_frequency = command_in_.frequency;
    // the response ratios over periods k (one) or k-1, k (two); the first period is never used
    const int n = command_->completed();
    auto ratio = [&](int out, int in, int first, int last) {
      std::complex<double> y = 0.0, u = 0.0;
      for (int k = first; k <= last; ++k)
        y += command_->fourier(k, out), u += command_->fourier(k, in);
      return y / u;
    };
    if (n >= 3) {
      double change = 0.0;
      for (int out : {2, 3}) {
        if (out == 2 && !has_piston_) continue;
        if (out == 3 && !has_surface_) continue;
        const int in = out == 2 ? 0 : 1;
        const std::complex<double> last = ratio(out, in, n - 1, n - 1);
        change = std::max(change, std::abs(last - ratio(out, in, n - 2, n - 2)) / std::abs(last));
      }
      m.response_settling = change;
      if (change <= kSettleTolerance) {
        if (has_piston_) {
          const auto h = ratio(2, 0, n - 2, n - 1);
          m.piston_gain = std::abs(h), m.piston_phase = std::arg(h);
        }
        if (has_surface_) {
          const auto h = ratio(3, 1, n - 2, n - 1);
          m.surface_gain = std::abs(h), m.surface_phase = std::arg(h);
        }
      }
    }
  }
  if (load_ && load_->completed() >= 1) {
    const int k = load_->completed() - 1;
    const double A = load_in_.amplitude;
    const auto [a_pos, b_pos] = load_->fit(k, 0, 1, 0.2 * A, 0.9 * A);
    const auto [a_neg, b_neg] = load_->fit(k, 0, 1, -0.9 * A, -0.2 * A);
    m.free_play = a_pos - a_neg;
    m.stiffness_positive = 1.0 / b_pos;
    m.stiffness_negative = 1.0 / b_neg;
    // the work of the hinge moment on the surface over the period, oint M d(theta): what the
    // linkage and the actuator take from the load (dissipated, the loop run clockwise in
    // (theta, M)); negative when the held actuator feeds energy into the loop. The moment is 0
    // at the period's ends (a triangle from 0), so this is -oint theta dM, the loop's area in
    // (M, theta) run the other way, whether or not the loop closes.
    m.hysteresis = load_->loop_area(k, 1, 0);
  }
  return m;
}

std::optional<PeriodicInput> PeriodicAccumulator::drive() const {
  if (command_) return command_in_;
  if (load_) return load_in_;
  return std::nullopt;
}

std::pair<double, double> PeriodicAccumulator::sensed_response(const std::vector<double>& t,
                                                               const std::vector<double>& y,
                                                               double scale) const {
  const PeriodicMetrics exact = finish();
  if (!command_ || !std::isfinite(exact.surface_gain) || t.size() != y.size()) return {kNaN, kNaN};
  const int n = command_->completed();
  PeriodSamples s(command_in_, 1, 3);
  for (std::size_t i = 0; i < t.size(); ++i) s.add(t[i], std::span<const double>(&y[i], 1));
  if (s.completed() != n) return {kNaN, kNaN};
  std::complex<double> out = 0.0, in = 0.0;
  for (int k = n - 2; k <= n - 1; ++k) out += s.fourier(k, 0), in += command_->fourier(k, 1);
  const std::complex<double> h = scale * out / in;
  return {std::abs(h), std::arg(h)};
}

std::pair<double, double> PeriodicAccumulator::sensed_loop(const std::vector<double>& t,
                                                           const std::vector<double>& moment,
                                                           const std::vector<double>& angle) const {
  if (!load_ || load_->completed() < 1 || t.size() != moment.size() || t.size() != angle.size())
    return {kNaN, kNaN};
  PeriodSamples s(load_in_, 2, 2);
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double v[2] = {moment[i], angle[i]};
    s.add(t[i], v);
  }
  if (s.completed() != load_->completed()) return {kNaN, kNaN};
  const int k = s.completed() - 1;
  const double A = load_in_.amplitude;  // the branches as finish() reads them
  const double a_pos = s.fit(k, 0, 1, 0.2 * A, 0.9 * A).first;
  const double a_neg = s.fit(k, 0, 1, -0.9 * A, -0.2 * A).first;
  return {s.loop_area(k, 1, 0), a_pos - a_neg};  // oint M dtheta, as finish()
}

}  // namespace rodend
