// Metrics of an output driven through a linkage against the same linkage with every joint ideal
// (scenes with surface_angle_command, ideal_surface_rate and ideal_surface_acceleration and a
// single-frequency periodic command: planar-linkage). Read from every accepted step, over the
// whole run after the command's first period (the start-up transient), so no sample interval
// enters them.
#pragma once

#include <array>
#include <optional>

#include "core/scene.hpp"
#include "sweep/periodic_metrics.hpp"

namespace rodend {

struct LinkageMetrics {
  double angle_error_percent, rate_fluctuation, acceleration_fluctuation;
  double main_frequency, main_frequency_amplitude;
};

class LinkageMetricsAccumulator {
 public:
  explicit LinkageMetricsAccumulator(const Scene& scene);
  bool active() const { return input_.has_value(); }
  void on_step(const SignalFrame& f);
  /// NaN where the run is too short (the main frequency: one whole period after the first).
  LinkageMetrics finish() const;

  static constexpr int kHarmonics = 8;  ///< multiples of the command's frequency searched

 private:
  std::optional<PeriodicInput> input_;
  double angle_error_ = 0.0, rate_error_ = 0.0, acceleration_error_ = 0.0;
  double ideal_min_ = 0.0, ideal_max_ = 0.0;
  bool seen_ = false;
  /// the shaft's acceleration, one PeriodSamples per harmonic h (its frequency h f)
  std::vector<PeriodSamples> harmonics_;
};

}  // namespace rodend
