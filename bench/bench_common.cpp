// rodend-bench's shared pieces (bench/bench_common.hpp).
#include "bench/bench_common.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace rodend::bench {

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

std::unique_ptr<Scene> build(const std::string& name) {
  return make_scene(name, ParameterSet::defaults_for(name));
}

IntegratorSettings preset_for(const Scene& scene, const std::string& name) {
  const auto s = preset_settings(scene.name(), name);
  if (!s) throw std::invalid_argument("unknown preset " + name);
  return *s;
}

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

/// computes the summary metrics from every step (the driver then also refines impact peaks on
/// the interpolant), as a study case does; without, nothing observes the steps.
RunMeasure run_once(const Scene& scene, const IntegratorSettings& s, double end,
                    bool with_metrics) {
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

}  // namespace rodend::bench
