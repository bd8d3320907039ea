// Diagnostic features of a record (docs/health-monitoring.md): the high-frequency content of a
// signal, over the run and in windows after contact onsets. One code for the exact signal (the
// accepted-step frames) and for a sensor's samples (sweep/sensor_channel.hpp): both are a
// series (t, u) read as its piecewise-linear interpolant.
#pragma once

#include <limits>
#include <vector>

#include "sweep/sensor_channel.hpp"

namespace rodend {

/// The part of a series above a cut-off: u less its second-order Butterworth low-pass (the
/// high-pass s^2 + sqrt2 w s over s^2 + sqrt2 w s + w^2), integrated exactly between the
/// series' points; its mean square over the series, and its largest magnitude in the windows
/// [t_o, t_o + window] after given onset times, averaged over the onsets.
class HighPassFeature {
 public:
  HighPassFeature(double cutoff_hz, double window);
  /// The next point of the series (times increasing).
  void add(double t, double u);
  /// A contact onset at t (not before the last point added).
  void onset(double t);
  /// The high-passed series' mean square over the series' span (NaN with fewer than 2 points).
  double mean_square() const;
  /// Mean over the onsets whose window ended within the series of the largest |high-passed|
  /// value at the points inside the window (NaN without such an onset).
  double onset_peak_mean() const;

 private:
  void close_windows(double t);
  LowPass low_;
  double window_;
  bool started_ = false;
  double t0_ = 0.0, t_ = 0.0, u_ = 0.0, hp_ = 0.0, integral_ = 0.0;
  std::vector<double> open_, open_peak_;  // onsets whose window is under way, their peaks
  double peak_sum_ = 0.0;
  int closed_ = 0;
};

/// Replays a sensor's samples through a feature, with the onsets in time order among them.
void replay(HighPassFeature& f, const std::vector<double>& times, const std::vector<double>& values,
            const std::vector<double>& onsets);

}  // namespace rodend
