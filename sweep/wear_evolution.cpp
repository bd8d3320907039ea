// The wear-evolution loop: duty cycles on surfaces worn by the cycles before.
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

/// The evolution histories, one row per update (row 0: as manufactured).
struct EvolutionTable {
  std::vector<double> cycles, per_update, axial, max, backlash, volume, depth_ball, depth_socket;

  void add_row(double cycles_so_far, double n, const JointPlay& p, const WornSurfaces& w) {
    cycles.push_back(cycles_so_far);
    per_update.push_back(n);
    axial.push_back(p.axial_clearance);
    max.push_back(p.max_clearance);
    backlash.push_back(p.surface_backlash);
    volume.push_back(w.ball.volume() + w.socket.volume());
    depth_ball.push_back(w.ball.max_depth().depth);
    depth_socket.push_back(w.socket.max_depth().depth);
  }

  /// The first cycles at which `col` reaches a limit, linear between the rows around it.
  double crossing(const std::vector<double>& col, double limit) const {
    if (!(limit > 0.0) || col.empty()) return kNaN;
    const std::size_t k = col.size() - 1;
    if (col[k] < limit) return kNaN;
    if (k == 0) return 0.0;
    const double f = (limit - col[k - 1]) / (col[k] - col[k - 1]);
    return cycles[k - 1] + std::clamp(f, 0.0, 1.0) * (cycles[k] - cycles[k - 1]);
  }

  /// The columns as the case file's /evolution arrays.
  void append_to(History& history) const {
    const std::string g = "evolution";
    const std::size_t rows = cycles.size();
    auto add = [&](const char* name, const char* unit, const char* what,
                   const std::vector<double>& col) {
      history.arrays.push_back(case_array(g, name, unit, what, {rows}, col));
    };
    add("cycles", "1", "duty cycles applied so far", cycles);
    add("cycles_per_update", "1", "duty cycles the update stands for (0 in row 0)", per_update);
    add("axial_clearance", "m", "half the free play of the ball along the rod axis", axial);
    add("max_clearance", "m", "largest local clearance over directions in the mechanism plane",
        max);
    add("surface_backlash", "rad", "free play of the surface angle (backlash at the surface)",
        backlash);
    add("worn_volume", "m^3", "worn volume of ball and socket", volume);
    add("max_depth_ball", "m", "deepest cell of the ball's map", depth_ball);
    add("max_depth_socket", "m", "deepest cell of the socket's map", depth_socket);
  }
};

/// The loop's state: the surfaces worn so far and what the record reports of it.
struct Evolution {
  std::shared_ptr<WornSurfaces> worn;
  EvolutionTable table;
  double cycles = 0.0, sliding_work = 0.0, to_limit = kNaN;
  long updates = 0;
  RunStatus status = RunStatus::ok;
  std::string message;
  MetricValues first{};
};

/// One duty cycle on the surfaces worn so far, and the update it makes; false when the loop
/// ends (a failed cycle, nothing worn, a limit or a bound reached).
bool run_update(const CaseSpec& spec, const Scene& base, Evolution& e, CaseRecord& rec,
                History& history) {
  const WearEvolutionSettings& ev = spec.wear_evolution;
  std::unique_ptr<Scene> owned;
  const Scene* scene = &base;
  if (e.updates > 0) {
    owned = base.with_worn_surfaces(e.worn);
    scene = owned.get();
  }
  CaseObserver obs(*scene, spec, e.updates == 0 ? &history : nullptr);
  // an exception inside the run is its internal_error; one outside it, run_case's
  RunResult r = simulate(*scene, spec.integrator, spec.time, obs, spec.health);
  rec.steps_accepted += r.stats.steps_accepted;
  rec.steps_rejected += r.stats.steps_rejected;
  rec.rhs_calls += r.stats.rhs_calls;
  rec.friction_switches += r.stats.friction_switches;
  rec.t_reached = r.stats.t_reached;
  if (e.updates == 0) e.first = obs.finish(r.stats);
  ++e.updates;
  if (r.status == RunStatus::ok && r.final_state.empty()) {
    r.status = RunStatus::non_finite_state;
    r.message = "no final state";
  }
  if (r.status != RunStatus::ok) {
    e.status = r.status;
    e.message = "duty cycle of wear update " + std::to_string(e.updates) + " (after " +
                std::to_string(e.cycles) + " cycles): " + r.message;
    return false;
  }
  if (e.updates == 1)
    e.table.add_row(0.0, 0.0, *base.joint_play(spec.time.end, r.final_state.data()), *e.worn);
  const WearAccumulator& w = *obs.wear();
  const double depth = std::max(w.ball().max_depth().depth, w.socket().max_depth().depth);
  if (!(depth > 0.0)) return false;  // this duty cycle wears nothing: the joint keeps its play
  double n = ev.cycles_per_update;
  if (ev.max_depth_change > 0.0) n = std::min(n, ev.max_depth_change / depth);
  n = std::min(n, ev.max_cycles - e.cycles);
  if (!(n > 0.0)) return false;
  auto next = std::make_shared<WornSurfaces>(*e.worn);
  next->ball.add_scaled(w.ball(), n);
  next->socket.add_scaled(w.socket(), n);
  e.cycles += n;
  e.sliding_work += n * obs.sliding_work();
  const auto probe = base.with_worn_surfaces(next);
  e.table.add_row(e.cycles, n, *probe->joint_play(spec.time.end, r.final_state.data()), *next);
  e.worn = std::move(next);
  const double a = e.table.crossing(e.table.axial, ev.clearance_limit);
  const double b = e.table.crossing(e.table.backlash, ev.backlash_limit);
  e.to_limit = std::isnan(a) ? b : std::isnan(b) ? a : std::min(a, b);
  return std::isnan(e.to_limit) && e.cycles < ev.max_cycles && e.updates < ev.max_updates;
}

/// The record's status, metrics and the evolution arrays, once the loop has ended.
void record_evolution(const Evolution& e, CaseRecord& rec, History& history) {
  rec.status = e.status;
  rec.message = e.message;
  rec.metrics = e.first;
  metric(rec.metrics, MetricId::sliding_work) = e.sliding_work;
  record_wear_maps(e.worn->ball, e.worn->socket, rec.metrics, history);
  metric(rec.metrics, MetricId::wear_cycles) = e.cycles;
  metric(rec.metrics, MetricId::wear_updates) = static_cast<double>(e.updates);
  metric(rec.metrics, MetricId::cycles_to_limit) = e.to_limit;
  if (!e.table.axial.empty()) {
    metric(rec.metrics, MetricId::final_axial_clearance) = e.table.axial.back();
    metric(rec.metrics, MetricId::final_max_clearance) = e.table.max.back();
    metric(rec.metrics, MetricId::final_surface_backlash) = e.table.backlash.back();
  }
  e.table.append_to(history);
}

}  // namespace

CaseRecord run_wear_evolution(const CaseSpec& spec, History& history) {
  CaseRecord rec = start_record(spec);
  const auto clock0 = std::chrono::steady_clock::now();
  const auto base = make_scene(spec.scene, spec.parameters);
  rec.features = base->features();
  const WearModel& model = *base->wear_model();  // checked when the study was loaded
  Evolution e;
  e.worn = std::make_shared<WornSurfaces>();
  e.worn->ball = WearMap(model.ball_radius, model.n_longitude, model.n_latitude);
  e.worn->socket = WearMap(model.socket_radius, model.n_longitude, model.n_latitude);
  e.first.fill(kNaN);
  while (run_update(spec, *base, e, rec, history)) {
  }
  rec.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
  rec.finished_utc = utc_now();
  record_evolution(e, rec, history);
  return rec;
}

}  // namespace rodend
