// What one case collects while it runs: sampled histories, the metrics of every step, and the
// wear maps of a scene that models wear. Shared by run_case (sweep/runner.cpp) and the wear
// evolution (sweep/wear_evolution.hpp).
#pragma once

#include <atomic>
#include <optional>

#include "core/integrator.hpp"
#include "core/scene.hpp"
#include "core/wear.hpp"
#include "sweep/metrics.hpp"
#include "sweep/results.hpp"
#include "sweep/sensor_channel.hpp"
#include "sweep/study.hpp"

namespace rodend {

/// Interrupting a case in flight (the Python module's run_case): once set, the
/// case's next sample throws CaseInterrupted, which is no std::exception, so that no handler of
/// a case takes it for the case's failure; nothing of the case is recorded. Set from a signal
/// handler (lock-free); the batch runner never sets it (its cases in flight finish).
std::atomic<bool>& case_interrupt();
struct CaseInterrupted {};

/// A record with the case's identity (id, index, scene, coordinates), its start time and every
/// metric NaN: what run_case and the wear evolution fill in.
CaseRecord start_record(const CaseSpec& spec);

/// Collects the sampled histories of the recorded signals (when given a History), the metrics
/// of every step, and the wear the driver deposits.
class CaseObserver final : public RunObserver {
 public:
  /// `history` null: no histories and no step metrics (the later duty cycles of a wear
  /// evolution need only their wear).
  CaseObserver(const Scene& scene, const CaseSpec& spec, History* history);
  void on_sample(const SignalFrame& f) override;
  void on_step(const SignalFrame& f) override;
  bool wants_steps() const override { return history_ != nullptr; }
  bool wants_peak(ContactPeak::Kind kind, int, double t0, double bound) const override {
    return metrics_.wants_peak(kind, t0, bound);
  }
  void on_contact_peak(const ContactPeak& p) override { metrics_.on_contact_peak(p); }
  void on_contact_onset(double t, int, double v) override { metrics_.on_contact_onset(t, v); }
  void on_wear(const WearSource& s, double weight) override { wear_->add(s, weight); }
  bool wants_wear() const override { return wear_.has_value(); }

  MetricValues finish(const RunStats& s) const { return metrics_.finish(s); }
  /// The wear accumulated by the run (null when the scene does not model wear).
  const WearAccumulator* wear() const { return wear_ ? &*wear_ : nullptr; }
  /// Sliding work of the state at the last sample [J] (NaN without wear).
  double sliding_work() const { return sliding_work_; }
  /// Adds the wear metrics and the maps (group "wear") of this run to a case's record.
  void record_wear(MetricValues& m, History& h) const;
  /// The sensors' records (group "sensors"): per sensor its samples and their times; and the
  /// sensed_* metrics read from them.
  void record_sensors(MetricValues& m, History& h) const;
  /// The sensors of the case (those of spec.sensors its scene has), as recorded so far.
  const std::vector<SensorChannel>& sensors() const { return sensors_; }

 private:
  History* history_;
  MetricsAccumulator metrics_;
  std::optional<WearAccumulator> wear_;
  double sliding_work_;
  std::vector<SensorChannel> sensors_;  // with a history only
  bool sensors_started_ = false;
};

/// Writes wear metrics for the maps `ball`, `socket` into `m` and the maps, with their axes,
/// into `h.arrays` (group "wear").
void record_wear_maps(const WearMap& ball, const WearMap& socket, MetricValues& m, History& h);

/// A per-case array with its netCDF dimension names (the wear maps' latitude x longitude, the
/// radii per body, the wear evolution's columns per update).
CaseArray case_array(std::string group, std::string name, std::string unit, std::string description,
                     std::vector<std::size_t> dims, std::vector<double> values);

}  // namespace rodend
