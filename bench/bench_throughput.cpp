// rodend-bench part 2: simulated seconds per wall second over one extension-retraction cycle
// (2.4 s) of rod-end-kinematic and rod-end-actuator, per accuracy preset.
#include <cmath>
#include <cstdio>

#include "bench/bench_common.hpp"

namespace rodend::bench {
namespace {

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

}  // namespace

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

}  // namespace rodend::bench
