// Summary metrics of a case, computed from the frames the driver produces on every accepted
// step (so peaks are not limited by the sample interval).
#pragma once

#include <array>
#include <limits>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "core/integrator.hpp"
#include "sweep/feature_metrics.hpp"
#include "sweep/linkage_metrics.hpp"
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
  /// [Hz] cut-off of the anti-alias low-pass of the rig metrics (ButterworthLowPass); 0 = off
  double lowpass_cutoff = 1000.0;
  int lowpass_order = 4;  ///< [-] order of that Butterworth low-pass
  /// [Hz] the diagnostic features' high-pass: above the linkage's 71 Hz mode and the commands
  double feature_highpass = 200.0;
  /// [s] pressure_ripple's window after an onset: 0.7 periods of the linkage's 71 Hz mode
  double onset_window = 0.01;
};

/// A Butterworth low-pass of order n and cut-off f_c, run forward (causal, as the anti-alias
/// filter of an accelerometer's conditioning) over a non-uniform sequence of samples: the analog
/// filter as cascaded second-order sections (and one first-order section for odd n), each
/// integrated exactly over a step with its input taken linear between the step ends
/// (first-order hold: exact for a piecewise-linear input to the first section; for the later
/// sections, whose input is the previous one's output, the hold is second order in the step).
/// No resampling, and no step is too large for stability. |H(f)|^2 = 1 / (1 + (f/f_c)^(2n)):
/// gain 1/sqrt(2) at f_c for every order.
class ButterworthLowPass {
 public:
  ButterworthLowPass(double cutoff_hz, int order);
  /// Start at rest at the constant input u (output u); returns u.
  double reset(double u);
  /// Advance by h [s] to the next sample u (the input linear in between); returns the output.
  double step(double h, double u);

 private:
  struct Section {
    double zeta = 0.0;  // damping ratio; < 0 marks a first-order section
    double x0 = 0.0, x1 = 0.0;
  };
  double omega_ = 0.0;  // [rad/s] 2 pi f_c
  std::vector<Section> sections_;
  double u_prev_ = 0.0;
};

/// The value below which the fraction q of `values` lies, linear between order statistics
/// (the "type 7" definition: q = 0 the smallest, 0.5 the median, 1 the largest); NaN when empty.
double percentile(std::vector<double> values, double q);

/// What a rig reads from the per-revolution records of the steady window (RigRevolution).
struct RigRevolution {
  double peak = 0.0;  ///< [m/s^2] peak |slider acceleration| of the revolution
  double min = std::numeric_limits<double>::infinity();   ///< [m/s^2] smallest (signed)
  double max = -std::numeric_limits<double>::infinity();  ///< [m/s^2] largest (signed)
  double filtered_peak = 0.0;                             ///< [m/s^2] the same, low-passed
  double filtered_min = std::numeric_limits<double>::infinity();
  double filtered_max = -std::numeric_limits<double>::infinity();
  double min_ecc_ratio = std::numeric_limits<double>::infinity();  ///< [-] min |e| / clearance
};
/// The rig metrics over the steady window of the revolution records (rig_metrics()).
struct RigMetrics {
  double median = std::numeric_limits<double>::quiet_NaN();  ///< [m/s^2] median peak
  double p95 = std::numeric_limits<double>::quiet_NaN();     ///< [m/s^2] 95th percentile peak
  double ptp = std::numeric_limits<double>::quiet_NaN();     ///< [m/s^2] max - min over window
  double filtered_median = std::numeric_limits<double>::quiet_NaN();
  double filtered_p95 = std::numeric_limits<double>::quiet_NaN();
  double filtered_ptp = std::numeric_limits<double>::quiet_NaN();
  double filtered_peak = std::numeric_limits<double>::quiet_NaN();  ///< [m/s^2] max peak
  double min_ecc_ratio = std::numeric_limits<double>::quiet_NaN();  ///< [-]
};
/// The steady window is the same as settled_peak()'s: revolutions N/2+1 .. N of N (the first
/// half, which holds the start-up transient, left out). NaN below 2 revolutions.
RigMetrics rig_metrics(std::span<const RigRevolution> revolutions);

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
  /// The sensed_* diagnostic features from the case's sensors' records
  /// (sweep/feature_metrics.cpp), into values finish() returned.
  void finish_sensed(const std::vector<SensorChannel>& sensors, MetricValues& v) const;

 private:
  /// The rig metrics (RigRevolution): one frame into the revolution under way, and the end of
  /// a revolution.
  void take_rig(const SignalFrame& f, double dt);
  void close_rig_revolution();
  void finish_rig(MetricValues& v) const;
  /// finish(): the crank-driven metrics (a revolution done) and the periodic ones.
  void finish_crank(MetricValues& v) const;
  void finish_periodic(MetricValues& v) const;

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
  /// on_step, by the feature of the scene each part serves (in this order).
  void step_contact(const SignalFrame& f, double t, double dt);
  void first_episode_begins(const SignalFrame& f, double t, double eccentricity);
  void first_episode_ends(const SignalFrame& f, double t);
  void step_surface(const SignalFrame& f, double t);
  void step_command(const SignalFrame& f);
  void step_chambers(const SignalFrame& f);
  void step_crank(const SignalFrame& f, double t, double dt);
  void take_revolution(const SignalFrame& f, Revolution& r) const;
  void step_energy(const SignalFrame& f);
  std::vector<double> revolution_peaks_;  // [m/s^2] peak |slider acceleration| of each turn
  LinkageMetricsAccumulator linkage_;     // a linkage against its ideal
  PeriodicAccumulator periodic_;          // frequency response, free-play loop
  // the rig metrics: the revolution under way, the finished ones, the anti-alias low-pass
  RigRevolution rig_current_, rig_frame_;
  std::vector<RigRevolution> rig_revolutions_;
  std::optional<ButterworthLowPass> lowpass_;
  bool lowpass_started_ = false;
  // the diagnostic features (sweep/feature_metrics.cpp): exact surface acceleration and
  // chamber-1 pressure, the onsets' times
  std::optional<HighPassFeature> accel_hf_, pressure_hf_;
  std::vector<double> onset_times_;
  void finish_features(MetricValues& v) const;
};

}  // namespace rodend
