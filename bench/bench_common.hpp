// rodend-bench's shared pieces: options, clocks, scenes, presets, one measured run, formatting.
// Each part of the benchmark (bench_rhs.cpp, bench_throughput.cpp, bench_cvode.cpp) uses these;
// bench/rodend_bench.cpp runs the parts.
#pragma once

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/integrator.hpp"
#include "core/params.hpp"
#include "core/presets.hpp"
#include "core/scene.hpp"
#include "sweep/metrics.hpp"

namespace rodend::bench {

using nlohmann::json;

struct Options {
  bool quick = false;
  std::string json_path;
  bool rhs = true, throughput = true, cvode = true;
};

// --- clocks and statistics ----------------------------------------------------------------------

struct Stamp {
  double wall;  ///< steady_clock [s]
  double cpu;   ///< this thread's CPU time [s]
};

Stamp now();
double median(std::vector<double> v);
json load_average();
std::string load_string();

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- scenes -------------------------------------------------------------------------------------

std::unique_ptr<Scene> build(const std::string& name);

class NullObserver final : public RunObserver {};

/// What a study case computes besides its histories: the summary metrics from every step.
class MetricsObserver final : public RunObserver {
 public:
  explicit MetricsObserver(const Scene& s) : m_(s, MetricsSettings{}) {}
  void on_step(const SignalFrame& f) override { m_.on_step(f); }
  bool wants_steps() const override { return true; }
  void on_contact_onset(double t, int, double v) override { m_.on_contact_onset(t, v); }
  bool wants_peak(ContactPeak::Kind k, int, double t0, double bound) const override {
    return m_.wants_peak(k, t0, bound);
  }
  void on_contact_peak(const ContactPeak& p) override { m_.on_contact_peak(p); }
  MetricValues finish(const RunStats& s) const { return m_.finish(s); }

 private:
  MetricsAccumulator m_;
};

// --- accuracy presets ---------------------------------------------------------------------------

/// The accuracy presets, resolved per scene by core (core/presets.hpp): "fast", "balanced"
/// (the default, rodend::kDefaultPreset) and "reference".
IntegratorSettings preset_for(const Scene& scene, const std::string& name);
constexpr const char* kPresetSource = "rodend::preset_settings(scene, preset) (core/presets.hpp)";
json settings_json(const IntegratorSettings& s);
std::string settings_string(const IntegratorSettings& s);

// --- runs ---------------------------------------------------------------------------------------

struct RunMeasure {
  RunResult result;
  MetricValues metrics{};
  double wall = kNaN, cpu = kNaN;
};

/// One run from t = 0 to `end`, samples every 1 ms (not kept). With `with_metrics` the observer
/// computes the summary metrics from every step (the driver then also refines impact peaks on
/// the interpolant), as a study case does; without, nothing observes the steps.
RunMeasure run_once(const Scene& scene, const IntegratorSettings& s, double end,
                    bool with_metrics = true);

/// Medians of repeated runs of one configuration (counts are deterministic: the first run's).
struct Repeated {
  IntegratorSettings settings;
  std::string label;
  std::vector<double> walls, cpus;
  RunMeasure first;
  bool have = false;

  void add(const RunMeasure& m) {
    if (!have) first = m;
    have = true;
    walls.push_back(m.wall);
    cpus.push_back(m.cpu);
  }
  bool ok() const { return have && first.result.status == RunStatus::ok; }
  double wall() const { return median(walls); }
  double cpu() const { return median(cpus); }
  double rhs() const { return static_cast<double>(first.result.stats.rhs_calls); }
};

constexpr double kCycle = 2.4;  // one extension-retraction cycle of the default motion [s]

// --- 2. throughput ------------------------------------------------------------------------------

struct ThroughputRow {
  std::string scene, preset;
  Repeated rep;   ///< with the metrics observer (as a study case)
  Repeated bare;  ///< nothing observing the steps
};

/// the scenes with the whole mechanism, measured by parts 2 and 3
inline const std::vector<std::string> kMechScenes = {"rod-end-kinematic", "rod-end-actuator"};

// --- formatting ---------------------------------------------------------------------------------

std::string fmt(const char* f, double v);
void rule(int width);

// --- the parts ----------------------------------------------------------------------------------

/// 1. Right-hand-side cost per scene; returns each scene's cpu cost per call [ns].
std::map<std::string, double> part_rhs(const Options& opt, json& out);
/// 2. Throughput over one cycle per mechanism scene and preset.
std::vector<ThroughputRow> part_throughput(const Options& opt,
                                           const std::map<std::string, double>& rhs_ns_cpu,
                                           json& out);
/// 3. CVODE against the default preset at equal achieved error.
void part_cvode(const Options& opt, const std::vector<ThroughputRow>& tp, json& out);

}  // namespace rodend::bench
