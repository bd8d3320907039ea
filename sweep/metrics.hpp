// Summary metrics of a case, computed from the frames the driver produces on every accepted
// step (so peaks are not limited by the sample interval).
#pragma once

#include <array>
#include <limits>
#include <span>
#include <string_view>
#include <vector>

#include "core/integrator.hpp"
#include "sweep/periodic_metrics.hpp"

namespace rodend {

enum class MetricId : int {
#define RODEND_METRIC(id, unit, doc) id,
#include "sweep/metrics.def"
#undef RODEND_METRIC
  count_
};
inline constexpr int metric_count = static_cast<int>(MetricId::count_);

struct MetricSpec {
  std::string_view name;
  std::string_view unit;
  std::string_view description;
};
std::span<const MetricSpec> metric_catalogue();

using MetricValues = std::array<double, metric_count>;
/// The value of metric `id` in `v`.
inline double& metric(MetricValues& v, MetricId id) {
  return v[static_cast<std::size_t>(id)];
}

/// Settings of the metrics (study key "metrics").
struct MetricsSettings {
  double post_impact_window = 0.05;        ///< [s] window for the eccentricity oscillation
  double surface_motion_threshold = 1e-3;  ///< [rad] surface counts as moving beyond this
};

/// The settled peak of a crank-driven response from the peak |slider acceleration| of each full
/// revolution (`revolution_peaks`, in order): the largest over the second half of the
/// revolutions, so the transient of the first half is left out and one window holds a whole cycle
/// of a response that repeats every revolution, every few revolutions, or irregularly (a journal
/// that leaves the bearing wall every 8-10 turns); with the median of the window's peaks (the
/// typical revolution) and the settling check.
struct SettledPeak {
  double peak = std::numeric_limits<double>::quiet_NaN();    ///< [m/s^2] max over the window
  double median = std::numeric_limits<double>::quiet_NaN();  ///< [m/s^2] median over the window
  /// [-] largest |S(N-k) - S(N)| / S(N) for k = 1..settle_revolutions, S(M) the peak of a run
  /// cut after M revolutions: the last revolutions changed the settled peak by at most this
  double change = std::numeric_limits<double>::quiet_NaN();
};
inline constexpr int kSettleRevolutions = 5;  ///< revolutions the settling check looks back
SettledPeak settled_peak(std::span<const double> revolution_peaks);

/// Accumulates the metrics from step frames.
class MetricsAccumulator {
 public:
  MetricsAccumulator(const Scene& scene, const MetricsSettings& settings);
  void on_step(const SignalFrame& f);
  /// A contact episode latched by the driver (first contact time and impact speed come from
  /// here: exact onset, not the first frame in contact).
  void on_contact_onset(double t, double impact_speed);
  /// Whether a contact maximum inside the step that starts at t0, at most `bound`, could change
  /// a metric (RunObserver::wants_peak): every maximum of the first episode and of the
  /// post-impact window; later ones only when they could raise the run's maximum.
  bool wants_peak(ContactPeak::Kind kind, double t0, double bound) const;
  /// A maximum located by the driver inside the step that the next on_step ends.
  void on_contact_peak(const ContactPeak& p);
  /// Final values; the driver's stats supply the health metrics.
  MetricValues finish(const RunStats& stats) const;

 private:
  MetricsSettings settings_;
  // what the scene has (Scene::features)
  bool has_contact_ = false, has_surface_ = false, has_energy_ = false;
  bool has_chambers_ = false, has_kinetic_ = false, has_command_ = false;
  bool has_crank_ = false, has_joint_forces_ = false, has_crank_rate_ = false;
  double t_prev_ = 0.0, force_prev_ = 0.0, wear_prev_ = 0.0;
  bool first_step_ = true;
  MetricValues v_{};
  int episode_ = 0;  // contact episodes seen
  int onsets_ = 0;   // onsets latched by the driver
  bool in_contact_ = false;
  double ecc_min_ = 0.0, ecc_max_ = 0.0;
  double ecc_peak_pending_ = 0.0;   // [m] peak eccentricity inside the step that starts episode 1
  double first_onset_ = 0.0;        // [s] onset of the first episode (its duration)
  double dissipated_prev_ = 0.0;    // [J] dissipated energy at the previous step end
  double dissipated_before_ = 0.0;  // [J] ... at the last step end before the first onset
  double energy_scale_ = 0.0, max_residual_ = 0.0;
  SignalId command_signal_ = SignalId::actuator_command;
  double command_max_ = 0.0, command_min_ = 0.0;  // [m] extremes of the command so far
  /// Peaks of one crank revolution (crank-driven mechanisms).
  struct Revolution {
    double peak_acceleration = 0.0, peak_force = 0.0;
    double ecc_min = std::numeric_limits<double>::infinity(), ecc_max = 0.0;
  };
  double crank_start_ = 0.0;  // [rad] crank angle of the first frame
  long long revolution_ = 0;  // index of the revolution under way
  Revolution current_, last_, before_last_;
  std::vector<double> revolution_peaks_;  // [m/s^2] peak |slider acceleration| of each turn
  PeriodicAccumulator periodic_;          // frequency response, free-play loop
};

}  // namespace rodend
