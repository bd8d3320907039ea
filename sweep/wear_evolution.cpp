// The wear-evolution loop (issue 11): duty cycles on surfaces worn by the cycles before.
#include "sweep/wear_evolution.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "sweep/case_observer.hpp"
#include "sweep/results.hpp"

namespace rodend {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

CaseRecord run_wear_evolution(const CaseSpec& spec, History& history) {
  CaseRecord rec = start_record(spec);
  const auto clock0 = std::chrono::steady_clock::now();
  const WearEvolutionSettings& ev = spec.wear_evolution;

  const auto base = make_scene(spec.scene, spec.parameters);
  rec.features = base->features();
  const WearModel& model = *base->wear_model();  // checked when the study was loaded
  auto worn = std::make_shared<WornSurfaces>();
  worn->ball = WearMap(model.ball_radius, model.n_longitude, model.n_latitude);
  worn->socket = WearMap(model.socket_radius, model.n_longitude, model.n_latitude);

  // evolution histories, one row per update (row 0: as manufactured)
  std::vector<double> cycles_col, per_update_col, axial_col, max_col, backlash_col, volume_col,
      depth_ball_col, depth_socket_col;
  auto add_row = [&](double cycles, double n, const JointPlay& p, const WornSurfaces& w) {
    cycles_col.push_back(cycles);
    per_update_col.push_back(n);
    axial_col.push_back(p.axial_clearance);
    max_col.push_back(p.max_clearance);
    backlash_col.push_back(p.surface_backlash);
    volume_col.push_back(w.ball.volume() + w.socket.volume());
    depth_ball_col.push_back(w.ball.max_depth().depth);
    depth_socket_col.push_back(w.socket.max_depth().depth);
  };
  // the first cycles at which a limit is reached, linear between the rows around it
  auto crossing = [&](const std::vector<double>& col, double limit) {
    if (!(limit > 0.0) || col.empty()) return kNaN;
    const std::size_t k = col.size() - 1;
    if (col[k] < limit) return kNaN;
    if (k == 0) return 0.0;
    const double f = (limit - col[k - 1]) / (col[k] - col[k - 1]);
    return cycles_col[k - 1] + std::clamp(f, 0.0, 1.0) * (cycles_col[k] - cycles_col[k - 1]);
  };

  double cycles = 0.0, sliding_work = 0.0, to_limit = kNaN;
  long updates = 0;
  RunStatus status = RunStatus::ok;
  std::string message;
  MetricValues first{};
  first.fill(kNaN);
  for (;;) {
    std::unique_ptr<Scene> owned;
    const Scene* scene = base.get();
    if (updates > 0) {
      owned = base->with_worn_surfaces(worn);
      scene = owned.get();
    }
    CaseObserver obs(*scene, spec, updates == 0 ? &history : nullptr);
    // an exception inside the run is its internal_error; one outside it, run_case's
    RunResult r = simulate(*scene, spec.integrator, spec.time, obs, spec.health);
    rec.steps_accepted += r.stats.steps_accepted;
    rec.steps_rejected += r.stats.steps_rejected;
    rec.rhs_calls += r.stats.rhs_calls;
    rec.t_reached = r.stats.t_reached;
    if (updates == 0) first = obs.finish(r.stats);
    ++updates;
    if (r.status == RunStatus::ok && r.final_state.empty()) {
      r.status = RunStatus::non_finite_state;
      r.message = "no final state";
    }
    if (r.status != RunStatus::ok) {
      status = r.status;
      message = "duty cycle of wear update " + std::to_string(updates) + " (after " +
                std::to_string(cycles) + " cycles): " + r.message;
      break;
    }
    if (updates == 1)
      add_row(0.0, 0.0, *base->joint_play(spec.time.end, r.final_state.data()), *worn);

    const WearAccumulator& w = *obs.wear();
    const double depth = std::max(w.ball().max_depth().depth, w.socket().max_depth().depth);
    if (!(depth > 0.0)) break;  // this duty cycle wears nothing: the joint keeps its play
    double n = ev.cycles_per_update;
    if (ev.max_depth_change > 0.0) n = std::min(n, ev.max_depth_change / depth);
    n = std::min(n, ev.max_cycles - cycles);
    if (!(n > 0.0)) break;
    auto next = std::make_shared<WornSurfaces>(*worn);
    next->ball.add_scaled(w.ball(), n);
    next->socket.add_scaled(w.socket(), n);
    cycles += n;
    sliding_work += n * obs.sliding_work();
    const auto probe = base->with_worn_surfaces(next);
    add_row(cycles, n, *probe->joint_play(spec.time.end, r.final_state.data()), *next);
    worn = std::move(next);

    const double a = crossing(axial_col, ev.clearance_limit);
    const double b = crossing(backlash_col, ev.backlash_limit);
    to_limit = std::isnan(a) ? b : std::isnan(b) ? a : std::min(a, b);
    if (!std::isnan(to_limit)) break;
    if (cycles >= ev.max_cycles || updates >= ev.max_updates) break;
  }

  rec.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
  rec.finished_utc = utc_now();
  rec.status = std::string(to_string(status));
  rec.message = message;
  rec.metrics = first;
  metric(rec.metrics, MetricId::sliding_work) = sliding_work;
  record_wear_maps(worn->ball, worn->socket, rec.metrics, history);
  metric(rec.metrics, MetricId::wear_cycles) = cycles;
  metric(rec.metrics, MetricId::wear_updates) = static_cast<double>(updates);
  metric(rec.metrics, MetricId::cycles_to_limit) = to_limit;
  if (!axial_col.empty()) {
    metric(rec.metrics, MetricId::final_axial_clearance) = axial_col.back();
    metric(rec.metrics, MetricId::final_max_clearance) = max_col.back();
    metric(rec.metrics, MetricId::final_surface_backlash) = backlash_col.back();
  }
  const std::string g = "evolution";
  const std::size_t rows = cycles_col.size();
  history.arrays.push_back(
      case_array(g, "cycles", "1", "duty cycles applied so far", {rows}, cycles_col));
  history.arrays.push_back(case_array(g, "cycles_per_update", "1",
                                      "duty cycles the update stands for (0 in row 0)", {rows},
                                      per_update_col));
  history.arrays.push_back(case_array(g, "axial_clearance", "m",
                                      "half the free play of the ball along the rod axis", {rows},
                                      axial_col));
  history.arrays.push_back(case_array(
      g, "max_clearance", "m", "largest local clearance over directions in the mechanism plane",
      {rows}, max_col));
  history.arrays.push_back(case_array(g, "surface_backlash", "rad",
                                      "free play of the surface angle (backlash at the surface)",
                                      {rows}, backlash_col));
  history.arrays.push_back(
      case_array(g, "worn_volume", "m^3", "worn volume of ball and socket", {rows}, volume_col));
  history.arrays.push_back(case_array(g, "max_depth_ball", "m", "deepest cell of the ball's map",
                                      {rows}, depth_ball_col));
  history.arrays.push_back(case_array(
      g, "max_depth_socket", "m", "deepest cell of the socket's map", {rows}, depth_socket_col));
  return rec;
}

}  // namespace rodend
