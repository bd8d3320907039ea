// rodend-bench part 1: the cost of one right-hand-side call per scene, at states sampled from
// a short run (contact active for the contact scenes); ratios to rod-end-kinematic.
#include <algorithm>
#include <cstdio>

#include "bench/bench_common.hpp"

namespace rodend::bench {
namespace {

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

}  // namespace

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

}  // namespace rodend::bench
