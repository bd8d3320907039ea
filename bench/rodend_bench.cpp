// rodend-bench: the project's benchmark (bench/README.md).
//
//   1. rhs         cost of one right-hand-side call per scene, at states sampled from a short run
//                  (contact active for the contact scenes); ratios to rod-end-kinematic.
//   2. throughput  simulated seconds per wall second over one extension-retraction cycle
//                  (2.4 s) of rod-end-kinematic and rod-end-actuator, per accuracy preset.
//   3. cvode       CVODE (BDF, Adams) against the default preset at equal achieved error on a set
//                  of summary metrics, measured against a reference run: cost ratios.
//
// Own harness: std::chrono::steady_clock for wall time (plus the thread's CPU clock, to show what
// the machine's load did to the wall figures), medians of repeated measurements.
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/integrator.hpp"
#include "core/params.hpp"
#include "core/presets.hpp"
#include "core/scene.hpp"
#include "sweep/metrics.hpp"

#ifndef RODEND_BENCH_BUILD_TYPE
#define RODEND_BENCH_BUILD_TYPE "unknown"
#endif
#ifndef RODEND_BENCH_CXX_FLAGS
#define RODEND_BENCH_CXX_FLAGS "unknown"
#endif
#ifndef RODEND_GIT_REVISION
#define RODEND_GIT_REVISION "unknown"
#endif

namespace {

using namespace rodend;
using nlohmann::json;

// --- options ------------------------------------------------------------------------------------

struct Options {
  bool quick = false;
  std::string json_path;
  bool rhs = true, throughput = true, cvode = true;
};

void usage(std::FILE* out) {
  std::fprintf(
      out,
      "usage: rodend-bench [--quick] [--json FILE] [--only rhs,throughput,cvode]\n"
      "  --quick        fewer repetitions and a shorter CVODE ladder (< 30 s on an idle machine)\n"
      "  --json FILE    also write every figure as JSON\n"
      "  --only LIST    run only these parts (comma-separated)\n");
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") {
      o.quick = true;
    } else if (a == "--json" && i + 1 < argc) {
      o.json_path = argv[++i];
    } else if (a == "--only" && i + 1 < argc) {
      const std::string list = argv[++i];
      o.rhs = list.find("rhs") != std::string::npos;
      o.throughput = list.find("throughput") != std::string::npos;
      o.cvode = list.find("cvode") != std::string::npos;
      if (!o.rhs && !o.throughput && !o.cvode) {
        usage(stderr);
        std::exit(2);
      }
    } else if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(0);
    } else {
      std::fprintf(stderr, "rodend-bench: unknown argument '%s'\n", a.c_str());
      usage(stderr);
      std::exit(2);
    }
  }
  return o;
}

// --- clocks and statistics ----------------------------------------------------------------------

struct Stamp {
  double wall;  ///< steady_clock [s]
  double cpu;   ///< this thread's CPU time [s]
};

Stamp now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  return {wall, static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec)};
}

double median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

json load_average() {
  double l[3] = {0, 0, 0};
  if (getloadavg(l, 3) != 3) return nullptr;
  return json::array({l[0], l[1], l[2]});
}

std::string load_string() {
  double l[3] = {0, 0, 0};
  if (getloadavg(l, 3) != 3) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.2f %.2f %.2f", l[0], l[1], l[2]);
  return buf;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// --- scenes -------------------------------------------------------------------------------------

std::unique_ptr<Scene> build(const std::string& name) {
  return make_scene(name, ParameterSet::defaults_for(name));
}

/// A scene that forwards everything to another and records the states its right-hand side is
/// called at (every `stride`-th call), with their time and discrete state.
class RecordingScene final : public Scene {
 public:
  RecordingScene(const Scene& inner, long long stride) : inner_(inner), stride_(stride) {}

  std::string_view name() const override { return inner_.name(); }
  Features features() const override { return inner_.features(); }
  int state_size() const override { return inner_.state_size(); }
  void initial_state(double* x) const override { inner_.initial_state(x); }
  void state_scale(double* s) const override { inner_.state_scale(s); }
  std::span<const int> quaternion_offsets() const override { return inner_.quaternion_offsets(); }
  std::span<const int> audit_offsets() const override { return inner_.audit_offsets(); }
  void derivatives(double t, const double* x, const DiscreteState& d, double* dxdt) const override {
    if (calls_++ % stride_ == 0) {
      times.push_back(t);
      states.insert(states.end(), x, x + inner_.state_size());
      discrete.push_back(d);
    }
    inner_.derivatives(t, x, d, dxdt);
  }
  int contact_count() const override { return inner_.contact_count(); }
  ContactGap contact_gap(int c, const double* x) const override { return inner_.contact_gap(c, x); }
  double contact_clearance(int c) const override { return inner_.contact_clearance(c); }
  std::span<const SignalId> signals() const override { return inner_.signals(); }
  void outputs(double t, const double* x, const DiscreteState& d, SignalFrame& f) const override {
    inner_.outputs(t, x, d, f);
  }
  EnergyTerms energy(double t, const double* x, const DiscreteState& d) const override {
    return inner_.energy(t, x, d);
  }

  mutable std::vector<double> times, states;
  mutable std::vector<DiscreteState> discrete;

 private:
  const Scene& inner_;
  long long stride_;
  mutable long long calls_ = 0;
};

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
IntegratorSettings preset_for(const Scene& scene, const std::string& name) {
  const auto s = preset_settings(scene.name(), name);
  if (!s) throw std::invalid_argument("unknown preset " + name);
  return *s;
}
constexpr const char* kPresetSource = "rodend::preset_settings(scene, preset) (core/presets.hpp)";

json settings_json(const IntegratorSettings& s) {
  return {{"method", to_string(s.method)}, {"abs_tol", s.abs_tol},
          {"rel_tol", s.rel_tol},          {"step", s.step},
          {"max_step", s.max_step},        {"contact_onset", to_string(s.contact_onset)}};
}

std::string settings_string(const IntegratorSettings& s) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%s %.0e", std::string(to_string(s.method)).c_str(), s.rel_tol);
  return buf;
}

// --- 1. right-hand-side cost --------------------------------------------------------------------

/// How long the short run that supplies the states lasts, per scene [s] and its integrator.
double sampling_run_end(const std::string& scene) {
  if (scene == "impact-pair") return 2e-3;  // one impact lasts ~0.1 ms at 0.1 m/s
  return 0.3;
}

struct RhsResult {
  std::string scene;
  int states = 0, audit = 0, contacts = 0;
  int sampled = 0, in_contact = 0;  ///< states timed, of which with the contact active
  double ns_wall = kNaN, ns_cpu = kNaN;
  double ns_wall_min = kNaN, ns_wall_max = kNaN;
};

/// The states the right-hand side is timed at: up to 256, evenly through a short run; for a
/// contact scene, only states with the contact active (latched episode and penetration > 0),
/// if the run has any.
struct SampledStates {
  std::vector<double> t, x;
  std::vector<DiscreteState> d;
  std::size_t count = 0;
};

SampledStates sample_states(const Scene& scene, const std::string& name, RhsResult& r) {
  const int n = r.states;
  // a short run that records the states the integrator calls the right-hand side at
  IntegratorSettings is;  // dopri5 1e-6
  const double end = sampling_run_end(name);
  const TimeSettings ts{end, end / 100};
  NullObserver null;
  long long calls = 0;
  {
    RecordingScene count(scene, 1ll << 62);
    calls = simulate(count, is, ts, null).stats.rhs_calls;
  }
  const long long stride = std::max(1ll, calls / 20000);
  RecordingScene rec(scene, stride);
  simulate(rec, is, ts, null);
  const std::size_t m = rec.times.size();
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < m; ++i) {
    bool ok = true;
    if (r.contacts > 0) {
      const double* x = rec.states.data() + i * static_cast<std::size_t>(n);
      ok = rec.discrete[i].contacts[0].in_contact && scene.contact_gap(0, x).penetration > 0.0;
    }
    if (ok) candidates.push_back(i);
  }
  if (candidates.empty())
    for (std::size_t i = 0; i < m; ++i) candidates.push_back(i);
  const std::size_t k = std::min<std::size_t>(256, candidates.size());
  SampledStates out{std::vector<double>(k), std::vector<double>(k * static_cast<std::size_t>(n)),
                    std::vector<DiscreteState>(k), k};
  for (std::size_t j = 0; j < k; ++j) {
    const std::size_t i = candidates[j * candidates.size() / k];
    out.t[j] = rec.times[i];
    std::copy_n(rec.states.data() + i * static_cast<std::size_t>(n), n,
                out.x.data() + j * static_cast<std::size_t>(n));
    out.d[j] = rec.discrete[i];
    if (r.contacts > 0 && out.d[j].contacts[0].in_contact &&
        scene.contact_gap(0, out.x.data() + j * static_cast<std::size_t>(n)).penetration > 0.0)
      ++r.in_contact;
  }
  r.sampled = static_cast<int>(k);
  return out;
}

RhsResult bench_rhs(const std::string& name, int reps, int calls_per_rep) {
  RhsResult r;
  r.scene = name;
  const auto scene = build(name);
  const int n = scene->state_size();
  r.states = n;
  r.audit = static_cast<int>(scene->audit_offsets().size());
  r.contacts = scene->contact_count();
  const SampledStates st = sample_states(*scene, name, r);
  std::vector<double> dx(static_cast<std::size_t>(n));
  double acc = 0.0;
  auto one_rep = [&]() {
    std::size_t j = 0;
    for (int c = 0; c < calls_per_rep; ++c) {
      scene->derivatives(st.t[j], st.x.data() + j * static_cast<std::size_t>(n), st.d[j],
                         dx.data());
      acc += dx[static_cast<std::size_t>(c % n)];
      if (++j == st.count) j = 0;
    }
  };
  one_rep();  // warm-up: caches, branch predictors, lazy statics
  std::vector<double> wall, cpu;
  for (int rep = 0; rep < reps; ++rep) {
    const Stamp a = now();
    one_rep();
    const Stamp b = now();
    wall.push_back((b.wall - a.wall) / calls_per_rep * 1e9);
    cpu.push_back((b.cpu - a.cpu) / calls_per_rep * 1e9);
  }
  volatile double sink = acc;
  (void)sink;
  r.ns_wall = median(wall);
  r.ns_cpu = median(cpu);
  r.ns_wall_min = *std::min_element(wall.begin(), wall.end());
  r.ns_wall_max = *std::max_element(wall.begin(), wall.end());
  return r;
}

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
                    bool with_metrics = true) {
  MetricsObserver obs(scene);
  NullObserver null;
  RunObserver& o = with_metrics ? static_cast<RunObserver&>(obs) : null;
  const TimeSettings ts{end, 1e-3};
  RunMeasure m;
  const Stamp a = now();
  m.result = simulate(scene, s, ts, o);
  const Stamp b = now();
  m.wall = b.wall - a.wall;
  m.cpu = b.cpu - a.cpu;
  if (with_metrics) m.metrics = obs.finish(m.result.stats);
  return m;
}

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

// --- 3. CVODE at equal error --------------------------------------------------------------------

struct ErrorMetric {
  MetricId id;
  const char* name;
};
constexpr ErrorMetric kErrorMetrics[] = {
    {MetricId::first_contact_time, "first_contact_time"},
    {MetricId::first_impact_peak_force, "first_impact_peak_force"},
    {MetricId::max_contact_force, "max_contact_force"},
    {MetricId::max_eccentricity, "max_eccentricity"},
    {MetricId::final_surface_angle, "final_surface_angle"},
};
constexpr int kErrorMetricCount = static_cast<int>(std::size(kErrorMetrics));

double metric(const MetricValues& v, MetricId id) {
  return v[static_cast<std::size_t>(id)];
}

/// Per-metric scale of the error: |reference value|, except the final surface angle (about 0
/// after a full cycle), scaled on the surface's angular range over the reference run.
std::vector<double> error_scales(const MetricValues& ref) {
  std::vector<double> s;
  for (const auto& e : kErrorMetrics) {
    double v = std::abs(metric(ref, e.id));
    if (e.id == MetricId::final_surface_angle)
      v = std::max(
          v, metric(ref, MetricId::max_surface_angle) - metric(ref, MetricId::min_surface_angle));
    s.push_back(v > 0.0 ? v : 1.0);
  }
  return s;
}

struct ErrorBreakdown {
  std::vector<double> each;  ///< per metric, relative
  double max = kNaN;         ///< the error of a run: the largest
};

ErrorBreakdown run_error(const MetricValues& v, const MetricValues& ref,
                         const std::vector<double>& scale) {
  ErrorBreakdown e;
  e.max = 0.0;
  for (int i = 0; i < kErrorMetricCount; ++i) {
    const double a = metric(v, kErrorMetrics[i].id), b = metric(ref, kErrorMetrics[i].id);
    double err = std::abs(a - b) / scale[static_cast<std::size_t>(i)];
    if (!std::isfinite(err)) err = std::numeric_limits<double>::infinity();
    e.each.push_back(err);
    e.max = std::max(e.max, err);
  }
  return e;
}

/// Cost at a target error on a tolerance ladder. A method's error does not fall monotonically
/// as its tolerance tightens here (the metrics are peaks of impacts, and CVODE's cost depends on
/// how often its Newton iteration fails at contact transitions), so the rungs are first reduced
/// to their work-precision front: the rungs no other rung beats on both error and cost. Along
/// the front (sorted by error), log(cost) is interpolated linearly in log(error) between the
/// two rungs that bracket the target.
///   - target below the front's smallest error: extrapolated along the last two front rungs
///     (flagged "extrapolated"), if more cost buys less error there;
///   - target above the front's largest error (every working rung is more accurate than the
///     target; the looser rungs failed or were not tried): the cost of the cheapest rung, an
///     upper bound (flagged "bound").
struct Interpolated {
  double value = kNaN;
  bool extrapolated = false, bound = false;
  int lo = -1, hi = -1;  ///< rungs used (indices into the ladder)
  std::vector<int> front;
};

Interpolated cost_at_error(const std::vector<double>& err, const std::vector<double>& cost,
                           double target) {
  Interpolated r;
  std::vector<int> idx;  // usable rungs
  for (int i = 0; i < static_cast<int>(err.size()); ++i)
    if (std::isfinite(err[i]) && err[i] > 0.0 && std::isfinite(cost[i]) && cost[i] > 0.0)
      idx.push_back(i);
  if (idx.empty() || !(target > 0.0)) return r;
  std::sort(idx.begin(), idx.end(), [&](int a, int b) {
    return err[a] < err[b] || (err[a] == err[b] && cost[a] < cost[b]);
  });
  // front: by increasing error, each rung cheaper than every more accurate one
  for (int i : idx)
    if (r.front.empty() || cost[i] < cost[r.front.back()]) r.front.push_back(i);
  const auto& f = r.front;
  auto interp = [&](int a, int b) {
    const double la = std::log(err[a]), lb = std::log(err[b]);
    if (la == lb) return std::min(cost[a], cost[b]);
    const double t = (std::log(target) - la) / (lb - la);
    return std::exp(std::log(cost[a]) + t * (std::log(cost[b]) - std::log(cost[a])));
  };
  if (target >= err[f.back()]) {  // every working rung is at least as accurate as the target
    r.value = cost[f.back()];
    r.bound = target > err[f.back()];
    r.lo = r.hi = f.back();
    return r;
  }
  for (std::size_t j = 0; j + 1 < f.size(); ++j)
    if (err[f[j]] <= target && target <= err[f[j + 1]]) {
      r.value = interp(f[j], f[j + 1]);
      r.lo = f[j];
      r.hi = f[j + 1];
      return r;
    }
  if (f.size() >= 2) {  // below the front's smallest error
    r.value = interp(f[0], f[1]);
    r.extrapolated = true;
    r.lo = f[0];
    r.hi = f[1];
  }
  return r;
}

// --- formatting ---------------------------------------------------------------------------------

std::string fmt(const char* f, double v) {
  char buf[64];
  if (!std::isfinite(v)) return std::isinf(v) ? "inf" : "n/a";
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

void rule(int width) {
  for (int i = 0; i < width; ++i) std::putchar('-');
  std::putchar('\n');
}

}  // namespace

namespace {

/// The machine and build, printed and as JSON.
json machine_header(const Options& opt) {
  char host[256] = "unknown";
  gethostname(host, sizeof host - 1);
  json machine = {{"host", host},
                  {"hardware_threads", std::thread::hardware_concurrency()},
                  {"load_average_start", load_average()},
                  {"compiler", __VERSION__},
                  {"build_type", RODEND_BENCH_BUILD_TYPE},
                  {"bench_flags", RODEND_BENCH_CXX_FLAGS},
                  {"git_revision", RODEND_GIT_REVISION},
                  {"quick", opt.quick}};
  std::printf("rodend-bench%s  (git %s, %s build, bench flags: %s)\n", opt.quick ? " --quick" : "",
              RODEND_GIT_REVISION, RODEND_BENCH_BUILD_TYPE, RODEND_BENCH_CXX_FLAGS);
  std::printf("host %s, %u hardware threads, load average %s (1, 5, 15 min) at start\n", host,
              std::thread::hardware_concurrency(), load_string().c_str());
  std::printf(
      "wall = std::chrono::steady_clock; cpu = this thread's CPU clock (wall/cpu > 1: the "
      "machine was busy)\n");
  return machine;
}

const RhsResult* find_rhs(const std::vector<RhsResult>& rows, const char* n) {
  for (const auto& r : rows)
    if (r.scene == n) return &r;
  return nullptr;
}

/// Part 1's table, a row per scene; `kin` is rod-end-kinematic's row (the ratios' base).
json print_rhs_rows(const std::vector<RhsResult>& rows, const RhsResult* kin) {
  json jr = json::array();
  for (const auto& r : rows) {
    const double ratio = kin ? r.ns_wall / kin->ns_wall : kNaN;
    const double ratio_cpu = kin ? r.ns_cpu / kin->ns_cpu : kNaN;
    const std::string contact =
        r.contacts ? std::to_string(r.in_contact) + "/" + std::to_string(r.sampled) : "-";
    std::printf("%-18s %7d %7d %9s %12s %12s %10s %10s %14s\n", r.scene.c_str(), r.states, r.audit,
                contact.c_str(), fmt("%.0f", r.ns_wall).c_str(), fmt("%.0f", r.ns_cpu).c_str(),
                fmt("%.3f", ratio).c_str(), fmt("%.3f", ratio_cpu).c_str(),
                fmt("%.1f", r.ns_cpu / r.states).c_str());
    jr.push_back({{"scene", r.scene},
                  {"state_size", r.states},
                  {"audit_states", r.audit},
                  {"contacts", r.contacts},
                  {"states_timed", r.sampled},
                  {"states_in_contact", r.in_contact},
                  {"ns_per_call_wall_median", r.ns_wall},
                  {"ns_per_call_wall_min", r.ns_wall_min},
                  {"ns_per_call_wall_max", r.ns_wall_max},
                  {"ns_per_call_cpu_median", r.ns_cpu},
                  {"ratio_to_rod_end_kinematic_wall", ratio},
                  {"ratio_to_rod_end_kinematic_cpu", ratio_cpu}});
  }
  return jr;
}

/// Part 1's ratios: the actuator's and the gravity drop's cost against rod-end-kinematic's.
json print_rhs_ratios(const std::vector<RhsResult>& rows, const RhsResult* kin) {
  json checks;
  const RhsResult* act = find_rhs(rows, "rod-end-actuator");
  const RhsResult* servo = find_rhs(rows, "servo-actuator");
  const RhsResult* drop = find_rhs(rows, "gravity-drop");
  if (kin && act) {
    const double extra = act->ns_cpu - kin->ns_cpu;
    std::printf(
        "rod-end-actuator / rod-end-kinematic = %.2f (cpu %.2f): the actuator adds %.0f ns "
        "cpu per call",
        act->ns_wall / kin->ns_wall, act->ns_cpu / kin->ns_cpu, extra);
    if (servo)
      std::printf("; servo-actuator alone (actuator + equivalent mass) costs %.0f ns",
                  servo->ns_cpu);
    std::printf("\n");
    checks["actuator_over_kinematic_wall"] = act->ns_wall / kin->ns_wall;
    checks["actuator_over_kinematic_cpu"] = act->ns_cpu / kin->ns_cpu;
    checks["actuator_extra_ns_cpu"] = extra;
    if (servo) checks["servo_actuator_alone_ns_cpu"] = servo->ns_cpu;
  }
  if (kin && drop) {
    std::printf(
        "gravity-drop / rod-end-kinematic = %.3f (cpu %.3f): one body and the contact, "
        "without the mechanism's second body, springs and slider-crank\n",
        drop->ns_wall / kin->ns_wall, drop->ns_cpu / kin->ns_cpu);
    checks["gravity_drop_over_kinematic_wall"] = drop->ns_wall / kin->ns_wall;
    checks["gravity_drop_over_kinematic_cpu"] = drop->ns_cpu / kin->ns_cpu;
  }
  return checks;
}

/// 1. Right-hand-side cost per scene; returns each scene's cpu cost per call [ns].
std::map<std::string, double> part_rhs(const Options& opt, json& out) {
  std::map<std::string, double> rhs_ns_cpu;
  const int reps = opt.quick ? 5 : 15, calls = opt.quick ? 5000 : 20000;
  std::fprintf(stderr, "rodend-bench: right-hand-side cost...\n");
  std::vector<RhsResult> rows;
  for (const SceneEntry& e : scene_catalogue())
    rows.push_back(bench_rhs(std::string(e.name), reps, calls));
  const RhsResult* kin = find_rhs(rows, "rod-end-kinematic");
  std::printf(
      "\n1. Right-hand-side cost per scene: median of %d repetitions of %d calls, cycling "
      "through states sampled from a short run (contact active where the scene has one);\n"
      "   ratio = cost / rod-end-kinematic's\n",
      reps, calls);
  rule(108);
  std::printf("%-18s %7s %7s %9s %12s %12s %10s %10s %14s\n", "scene", "states", "(audit)",
              "contact", "ns/call wall", "ns/call cpu", "ratio wall", "ratio cpu", "ns/state cpu");
  rule(108);
  for (const auto& r : rows) rhs_ns_cpu[r.scene] = r.ns_cpu;
  const json jr = print_rhs_rows(rows, kin);
  rule(108);
  const json checks = print_rhs_ratios(rows, kin);
  std::printf("load average after part 1: %s\n", load_string().c_str());
  out["rhs"] = {{"repetitions", reps},
                {"calls_per_repetition", calls},
                {"scenes", jr},
                {"ratios", checks},
                {"load_average_after", load_average()}};
  return rhs_ns_cpu;
}

const std::vector<std::string> kMechScenes = {"rod-end-kinematic", "rod-end-actuator"};

/// Part 2's runs: each mechanism scene under each preset, with and without the metrics.
std::vector<ThroughputRow> measure_throughput(int reps) {
  std::vector<std::string> presets;
  for (std::string_view p : preset_names()) presets.emplace_back(p);
  std::vector<ThroughputRow> tp;
  for (const auto& name : kMechScenes) {
    const auto scene = build(name);
    for (const auto& p : presets) {
      ThroughputRow row{name, p, {}, {}};
      row.rep.settings = row.bare.settings = preset_for(*scene, p);
      // the runs of one scene are interleaved over presets so a change of load hits them alike
      tp.push_back(std::move(row));
    }
    for (int r = 0; r < reps; ++r)
      for (auto& row : tp)
        if (row.scene == name) {
          row.rep.add(run_once(*scene, row.rep.settings, kCycle));
          row.bare.add(run_once(*scene, row.bare.settings, kCycle, false));
        }
  }
  return tp;
}

/// One row of part 2's table, printed and as JSON.
json print_throughput_row(const ThroughputRow& row, const std::map<std::string, double>& rhs_ns) {
  const auto& st = row.rep.first.result.stats;
  const double ns = rhs_ns.count(row.scene) ? rhs_ns.at(row.scene) : kNaN;
  const double share = static_cast<double>(st.rhs_calls) * ns * 1e-9 / row.rep.cpu();
  std::printf("%-18s %-10s %-16s %7s %9s %9s %13s %13s %12s %9lld %8lld %10s\n", row.scene.c_str(),
              row.preset.c_str(), settings_string(row.rep.settings).c_str(),
              std::string(to_string(row.rep.first.result.status)).c_str(),
              fmt("%.3f", row.rep.wall()).c_str(), fmt("%.3f", row.rep.cpu()).c_str(),
              fmt("%.2f", kCycle / row.rep.wall()).c_str(),
              fmt("%.2f", kCycle / row.rep.cpu()).c_str(),
              fmt("%.2f", kCycle / row.bare.cpu()).c_str(), st.rhs_calls,
              st.steps_accepted + st.steps_rejected, fmt("%.0f%%", 100.0 * share).c_str());
  return {{"scene", row.scene},
          {"preset", row.preset},
          {"settings", settings_json(row.rep.settings)},
          {"status", to_string(row.rep.first.result.status)},
          {"runs", row.rep.walls.size()},
          {"wall_s_median", row.rep.wall()},
          {"cpu_s_median", row.rep.cpu()},
          {"wall_s_all", row.rep.walls},
          {"sim_s_per_wall_s", kCycle / row.rep.wall()},
          {"sim_s_per_cpu_s", kCycle / row.rep.cpu()},
          {"bare_wall_s_median", row.bare.wall()},
          {"bare_cpu_s_median", row.bare.cpu()},
          {"bare_sim_s_per_wall_s", kCycle / row.bare.wall()},
          {"bare_sim_s_per_cpu_s", kCycle / row.bare.cpu()},
          {"rhs_share_of_cpu", std::isfinite(share) ? json(share) : json()},
          {"rhs_calls", st.rhs_calls},
          {"steps_accepted", st.steps_accepted},
          {"steps_rejected", st.steps_rejected},
          {"contact_onsets", st.contact_onsets}};
}

/// 2. Throughput over one cycle per mechanism scene and preset.
std::vector<ThroughputRow> part_throughput(const Options& opt,
                                           const std::map<std::string, double>& rhs_ns_cpu,
                                           json& out) {
  const int reps = opt.quick ? 1 : 5;
  std::fprintf(stderr, "rodend-bench: throughput...\n");
  std::vector<ThroughputRow> tp = measure_throughput(reps);
  std::printf(
      "\n2. Throughput over one extension-retraction cycle (%.1f s simulated), median of %d "
      "run%s;\n   the summary metrics computed on every step as in a study case (\"bare\": "
      "nothing observing the steps); \"rhs share\": rhs calls x part 1's cpu cost per call "
      "/ cpu time\n",
      kCycle, reps, reps > 1 ? "s" : "");
  std::printf("   presets: %s\n", kPresetSource);
  rule(144);
  std::printf("%-18s %-10s %-16s %7s %9s %9s %13s %13s %12s %9s %8s %10s\n", "scene", "preset",
              "settings", "status", "wall [s]", "cpu [s]", "sim s/wall s", "sim s/cpu s",
              "bare s/cpu s", "rhs", "steps", "rhs share");
  rule(144);
  json jt = json::array();
  for (const auto& row : tp) jt.push_back(print_throughput_row(row, rhs_ns_cpu));
  rule(144);
  std::printf("load average after part 2: %s\n", load_string().c_str());
  out["throughput"] = {{"simulated_s", kCycle},
                       {"preset_source", kPresetSource},
                       {"rows", jt},
                       {"load_average_after", load_average()}};
  return tp;
}

const std::vector<IntegratorMethod> kCvodeMethods = {IntegratorMethod::cvode_bdf,
                                                     IntegratorMethod::cvode_adams};

/// Part 3's reference run of a scene: dopri5 at 1e-12 (dense output, so the impact peaks are
/// refined on an interpolant as accurate as the method); fehlberg78 is not used: without dense
/// output its long steps miss force peaks that fall before the step where the penetration turns.
struct Reference {
  IntegratorSettings settings;
  RunMeasure run;
  std::vector<double> scale;
  double floor_err = kNaN;  ///< the reference's own error: the next looser run (1e-11) from it
};

std::optional<Reference> reference_run(const Scene& scene, const std::string& name,
                                       const IntegratorSettings& def) {
  Reference r;
  r.settings = def;
  r.settings.method = IntegratorMethod::dopri5;
  r.settings.abs_tol = r.settings.rel_tol = 1e-12;
  r.run = run_once(scene, r.settings, kCycle);
  if (r.run.result.status != RunStatus::ok) {
    std::printf("%s: reference run failed (%s)\n", name.c_str(), r.run.result.message.c_str());
    return std::nullopt;
  }
  r.scale = error_scales(r.run.metrics);
  IntegratorSettings check_s = r.settings;
  check_s.abs_tol = check_s.rel_tol = 1e-11;
  const RunMeasure chk = run_once(scene, check_s, kCycle);
  if (chk.result.status == RunStatus::ok)
    r.floor_err = run_error(chk.metrics, r.run.metrics, r.scale).max;
  return r;
}

/// One row of part 3's ladder table, printed and as JSON.
json print_ladder_row(const Repeated& c, const ErrorBreakdown& e) {
  std::string each;
  for (double v : e.each) each += fmt("%.1e", v) + " ";
  const auto& st = c.first.result.stats;
  std::printf("%-9s %-12s %6s %-22s %9s %9s %9s %8lld %7lld  %s\n", c.label.c_str(),
              std::string(to_string(c.settings.method)).c_str(),
              fmt("%.0e", c.settings.rel_tol).c_str(),
              std::string(to_string(c.first.result.status)).c_str(), fmt("%.2e", e.max).c_str(),
              fmt("%.3f", c.wall()).c_str(), fmt("%.3f", c.cpu()).c_str(), st.rhs_calls,
              st.steps_accepted + st.steps_rejected, each.c_str());
  return {{"label", c.label},
          {"settings", settings_json(c.settings)},
          {"status", to_string(c.first.result.status)},
          {"message", c.first.result.message},
          {"error", e.max},
          {"errors_per_metric", e.each},
          {"wall_s_median", c.wall()},
          {"cpu_s_median", c.cpu()},
          {"wall_s_all", c.walls},
          {"rhs_calls", st.rhs_calls},
          {"steps_accepted", st.steps_accepted},
          {"steps_rejected", st.steps_rejected}};
}

/// The ladder's rows after the default's (cfg[0]): their errors, printed; `ladder` gets them.
std::vector<ErrorBreakdown> print_ladder(const std::vector<Repeated>& cfg, const Reference& ref,
                                         json& ladder) {
  std::vector<ErrorBreakdown> errs;
  for (std::size_t i = 1; i < cfg.size(); ++i) {
    ErrorBreakdown e;
    if (cfg[i].ok()) {
      e = run_error(cfg[i].first.metrics, ref.run.metrics, ref.scale);
    } else {
      e.max = std::numeric_limits<double>::infinity();
      e.each.assign(kErrorMetricCount, kNaN);
    }
    errs.push_back(e);
    ladder.push_back(print_ladder_row(cfg[i], e));
  }
  return errs;
}

/// The presets' achieved errors, from part 2's runs.
json preset_errors(const std::vector<ThroughputRow>& tp, const std::string& name,
                   const Reference& ref) {
  json errors;
  std::string line;
  for (const auto& row : tp)
    if (row.scene == name && row.rep.ok()) {
      const double e = run_error(row.rep.first.metrics, ref.run.metrics, ref.scale).max;
      errors[row.preset] = e;
      line += "  " + row.preset + " " + fmt("%.2e", e);
    }
  if (!line.empty()) std::printf("achieved error of the presets:%s\n", line.c_str());
  return errors;
}

json interpolation_json(const Interpolated& in, const std::vector<double>& tol) {
  std::vector<double> v;
  for (int i : in.front) v.push_back(tol[static_cast<std::size_t>(i)]);
  return {{"extrapolated", in.extrapolated}, {"upper_bound", in.bound}, {"front_tolerances", v}};
}

/// A CVODE method's cost at the default's error, against the default's (d), printed and as JSON.
json method_cost(IntegratorMethod m, const std::vector<Repeated>& cfg,
                 const std::vector<ErrorBreakdown>& errs, const Repeated& d, double target) {
  std::vector<double> e, wall, cpu, rhs, tol;
  for (std::size_t i = 1; i < cfg.size(); ++i)
    if (cfg[i].settings.method == m) {
      e.push_back(errs[i - 1].max);
      wall.push_back(cfg[i].wall());
      cpu.push_back(cfg[i].cpu());
      rhs.push_back(cfg[i].rhs());
      tol.push_back(cfg[i].settings.rel_tol);
    }
  const Interpolated iw = cost_at_error(e, wall, target);
  const Interpolated ic = cost_at_error(e, cpu, target);
  const Interpolated ir = cost_at_error(e, rhs, target);
  const double rw = iw.value / d.wall(), rc = ic.value / d.cpu(), rr = ir.value / d.rhs();
  auto shown = [&](const Interpolated& in, double ratio) {
    std::string v = fmt("%.2f", ratio);
    if (in.bound) v = "<= " + v;
    if (in.extrapolated) v += " (extrapolated)";
    return v;
  };
  auto rungs = [&](const Interpolated& in) {
    if (in.lo < 0) return std::string("-");
    std::string r = fmt("%.0e", tol[static_cast<std::size_t>(in.lo)]);
    if (in.hi != in.lo) r += ".." + fmt("%.0e", tol[static_cast<std::size_t>(in.hi)]);
    return r;
  };
  const std::string name(to_string(m));
  std::printf(
      "%-12s cost / default at error %.2e: wall %s, cpu %s, rhs calls %s   "
      "(front rungs used: wall %s, cpu %s, rhs %s)\n",
      name.c_str(), target, shown(iw, rw).c_str(), shown(ic, rc).c_str(), shown(ir, rr).c_str(),
      rungs(iw).c_str(), rungs(ic).c_str(), rungs(ir).c_str());
  return {{"method", name},
          {"wall_s_at_default_error", iw.value},
          {"cpu_s_at_default_error", ic.value},
          {"rhs_calls_at_default_error", ir.value},
          {"ratio_wall", rw},
          {"ratio_cpu", rc},
          {"ratio_rhs_calls", rr},
          {"wall", interpolation_json(iw, tol)},
          {"cpu", interpolation_json(ic, tol)},
          {"rhs_calls", interpolation_json(ir, tol)}};
}

/// The configurations of a scene's ladder: the default, then each method's tolerances,
/// measured in rounds so that a change of the machine's load hits all of them alike.
std::vector<Repeated> run_ladder(const Scene& scene, const IntegratorSettings& def,
                                 const std::vector<double>& tols, int reps) {
  std::vector<Repeated> cfg;
  cfg.push_back({def, std::string(rodend::kDefaultPreset), {}, {}, {}, false});
  for (const IntegratorMethod m : kCvodeMethods)
    for (double tol : tols) {
      IntegratorSettings s = def;
      s.method = m;
      s.abs_tol = s.rel_tol = tol;
      cfg.push_back({s, "ladder", {}, {}, {}, false});
    }
  for (int r = 0; r < reps; ++r)
    for (auto& c : cfg) c.add(run_once(scene, c.settings, kCycle));
  return cfg;
}

/// Part 3 for one scene; null when its reference run failed.
json cvode_scene(const std::string& name, int reps, const std::vector<double>& tols,
                 const std::vector<ThroughputRow>& tp) {
  std::fprintf(stderr, "rodend-bench: CVODE ladder, %s...\n", name.c_str());
  const auto scene = build(name);
  const IntegratorSettings def = preset_for(*scene, std::string(rodend::kDefaultPreset));
  const std::optional<Reference> ref = reference_run(*scene, name, def);
  if (!ref) return json();
  const std::vector<Repeated> cfg = run_ladder(*scene, def, tols, reps);
  const Repeated& d = cfg[0];
  const ErrorBreakdown de = run_error(d.first.metrics, ref->run.metrics, ref->scale);
  std::printf("\n%s: reference %s (%lld rhs calls); dopri5 1e-11 differs from it by %s\n",
              name.c_str(), settings_string(ref->settings).c_str(), ref->run.result.stats.rhs_calls,
              fmt("%.1e", ref->floor_err).c_str());
  rule(150);
  std::printf("%-9s %-12s %6s %-22s %9s %9s %9s %8s %7s  %s\n", "run", "method", "tol", "status",
              "error", "wall [s]", "cpu [s]", "rhs", "steps",
              "error per metric: contact t, 1st peak, max F, max ecc, final angle");
  rule(150);
  json ladder = json::array();
  ladder.push_back(print_ladder_row(d, de));
  const std::vector<ErrorBreakdown> errs = print_ladder(cfg, *ref, ladder);
  rule(150);
  const json presets = preset_errors(tp, name, *ref);
  json jm = json::array();
  for (const IntegratorMethod m : kCvodeMethods) jm.push_back(method_cost(m, cfg, errs, d, de.max));
  std::printf("load average: %s\n", load_string().c_str());
  std::vector<std::string> metric_names;
  json ref_values;
  for (const auto& em : kErrorMetrics) {
    metric_names.emplace_back(em.name);
    ref_values[em.name] = metric(ref->run.metrics, em.id);
  }
  return {
      {"scene", name},
      {"reference", settings_json(ref->settings)},
      {"reference_rhs_calls", ref->run.result.stats.rhs_calls},
      {"reference_metrics", ref_values},
      {"error_scales", ref->scale},
      {"metrics", metric_names},
      {"reference_error_estimate", std::isfinite(ref->floor_err) ? json(ref->floor_err) : json()},
      {"default_settings", settings_json(def)},
      {"default_error", de.max},
      {"default_errors_per_metric", de.each},
      {"preset_errors", presets},
      {"runs", ladder},
      {"cvode_over_default", jm},
      {"load_average_after", load_average()}};
}

/// 3. CVODE against the default preset at equal achieved error.
void part_cvode(const Options& opt, const std::vector<ThroughputRow>& tp, json& out) {
  const int reps = opt.quick ? 1 : 3;
  const std::vector<double> tols =
      opt.quick
          ? std::vector<double>{1e-5, 1e-6, 1e-7, 1e-8, 1e-9}
          : std::vector<double>{1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9};
  json jc = json::array();
  std::printf("\n3. CVODE against the default preset (%s) at equal achieved error\n",
              std::string(rodend::kDefaultPreset).c_str());
  std::printf(
      "   error of a run = largest relative error over {first_contact_time, "
      "first_impact_peak_force, max_contact_force, max_eccentricity, final_surface_angle}\n"
      "   against a reference run (scales: |reference value|; the final surface angle on the "
      "surface's angular range).\n"
      "   CVODE's cost at the default's error: log-log interpolation along the work-precision "
      "front of its tolerance ladder; wall and cpu times median of %d run%s\n",
      reps, reps > 1 ? "s" : "");
  for (const auto& name : kMechScenes)
    if (json scene = cvode_scene(name, reps, tols, tp); !scene.is_null()) jc.push_back(scene);
  out["cvode"] = {{"default_preset", std::string(rodend::kDefaultPreset)},
                  {"repetitions", reps},
                  {"tolerances", tols},
                  {"scenes", jc}};
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  json out;
  out["machine"] = machine_header(opt);
  const auto t_start = now();
  std::map<std::string, double> rhs_ns_cpu;  // part 1's cpu cost per call, per scene
  if (opt.rhs) rhs_ns_cpu = part_rhs(opt, out);
  std::vector<ThroughputRow> tp;
  if (opt.throughput) tp = part_throughput(opt, rhs_ns_cpu, out);
  if (opt.cvode) part_cvode(opt, tp, out);
  const auto t_end = now();
  out["machine"]["load_average_end"] = load_average();
  out["machine"]["total_wall_s"] = t_end.wall - t_start.wall;
  std::printf("\ntotal %.1f s wall, %.1f s cpu; load average %s at the end\n",
              t_end.wall - t_start.wall, t_end.cpu - t_start.cpu, load_string().c_str());
  if (!opt.json_path.empty()) {
    std::ofstream f(opt.json_path);
    if (!f) {
      std::fprintf(stderr, "rodend-bench: cannot write %s\n", opt.json_path.c_str());
      return 1;
    }
    f << out.dump(2) << '\n';
    std::fprintf(stderr, "rodend-bench: wrote %s\n", opt.json_path.c_str());
  }
  return 0;
}
