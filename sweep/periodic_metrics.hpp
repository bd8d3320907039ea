// Metrics of a scene's single-frequency periodic inputs (Scene::periodic_inputs; derivations and
// the settling test in docs/inputs.md):
//   - the frequency response to a sine command: gain and phase of the piston and of the surface
//     at the drive frequency, by a one-frequency Fourier projection over whole, settled periods;
//   - the free-play loop of a triangle hinge moment: the surface angle against the moment over
//     the last whole period, its free-play, the loaded stiffness on each side and its area.
#pragma once

#include <complex>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "core/scene.hpp"

namespace rodend {

/// The samples (time, then `channels` values, linear between samples) of the last few whole
/// periods of a periodic input; older ones are dropped as the run goes.
class PeriodSamples {
 public:
  PeriodSamples(const PeriodicInput& in, int channels, int keep_periods);
  /// One sample at a time later than the previous one.
  void add(double t, std::span<const double> values);
  /// Whole periods completed so far (the input's cycles at most).
  int completed() const { return completed_; }
  /// Integral over period k (0-based, one of the periods kept) of channel c times
  /// exp(-i 2 pi f (t - start)), exact for the piecewise-linear interpolant.
  std::complex<double> fourier(int k, int c) const;
  /// Integral over period k of channel y d(channel x) (trapezoids): a loop's signed area.
  double loop_area(int k, int x, int y) const;
  /// Least-squares line y = a + b x over the times of period k at which channel x lies in
  /// [lo, hi] (the piecewise-linear interpolant, integrated exactly). {a, b}; NaN when x does
  /// not vary over them.
  std::pair<double, double> fit(int k, int x, int y, double lo, double hi) const;

 private:
  /// The samples of period k as segments: the rows within it plus its ends, interpolated.
  std::vector<double> period_rows(int k) const;
  PeriodicInput in_;
  int channels_, keep_;
  int completed_ = 0;
  std::size_t stale_ = 0;     // leading samples no longer needed
  std::vector<double> rows_;  // (t, values...) per sample
};

/// The frequency-response and free-play metrics of one case.
struct PeriodicMetrics {
  double drive_frequency, piston_gain, piston_phase, surface_gain, surface_phase, response_settling;
  double free_play, stiffness_positive, stiffness_negative, hysteresis;
};

/// Accumulates them from step frames.
class PeriodicAccumulator {
 public:
  explicit PeriodicAccumulator(const Scene& scene);
  bool active() const { return command_.has_value() || load_.has_value(); }
  void on_step(const SignalFrame& f);
  PeriodicMetrics finish() const;
  /// The input the metrics read over: the command, else the hinge moment (none: nullopt).
  std::optional<PeriodicInput> drive() const;
  /// surface_gain and surface_phase from a sensor's samples (t, y), linear between them, with
  /// the surface angle y x `scale` (1 for an angle, -1/(2 pi f)^2 for an acceleration): over the
  /// periods finish() uses, against the exact surface_angle_command. NaN when finish()'s are.
  std::pair<double, double> sensed_response(const std::vector<double>& t,
                                            const std::vector<double>& y, double scale) const;
  /// hysteresis and free_play from the samples of a moment and an angle sensor taken at the
  /// same times: {hysteresis, free_play}, NaN when they cannot be read.
  std::pair<double, double> sensed_loop(const std::vector<double>& t,
                                        const std::vector<double>& moment,
                                        const std::vector<double>& angle) const;

  /// The settling tolerance: the complex response ratios of the last two whole periods differ
  /// by at most this fraction of the last (0.5 %: 0.5 % of gain, 0.29 deg of phase).
  static constexpr double kSettleTolerance = 5e-3;

 private:
  std::optional<PeriodSamples> command_, load_;
  PeriodicInput command_in_{}, load_in_{};
  bool has_piston_ = false, has_surface_ = false;
  SignalId command_signal_ = SignalId::actuator_command;
};

}  // namespace rodend
