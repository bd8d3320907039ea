// rodend-bench part 3: CVODE (BDF, Adams) against the default preset at equal achieved error on
// a set of summary metrics, measured against a reference run: cost ratios.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "bench/bench_common.hpp"

namespace rodend::bench {
namespace {

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
  cfg.push_back({def, std::string(choice_name(rodend::kDefaultPreset)), {}, {}, {}, false});
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
  const IntegratorSettings def =
      preset_for(*scene, std::string(choice_name(rodend::kDefaultPreset)));
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

}  // namespace

/// 3. CVODE against the default preset at equal achieved error.
void part_cvode(const Options& opt, const std::vector<ThroughputRow>& tp, json& out) {
  const int reps = opt.quick ? 1 : 3;
  const std::vector<double> tols =
      opt.quick
          ? std::vector<double>{1e-5, 1e-6, 1e-7, 1e-8, 1e-9}
          : std::vector<double>{1e-4, 3e-5, 1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9};
  json jc = json::array();
  std::printf("\n3. CVODE against the default preset (%s) at equal achieved error\n",
              std::string(choice_name(rodend::kDefaultPreset)).c_str());
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
  out["cvode"] = {{"default_preset", std::string(choice_name(rodend::kDefaultPreset))},
                  {"repetitions", reps},
                  {"tolerances", tols},
                  {"scenes", jc}};
}

}  // namespace rodend::bench
