// Resolving: case `index` rebuilt from the base drafts and the axes, with the checks that
// interact between axes; every case checked once (its id kept); the study's CaseList.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <mutex>
#include <optional>

#include "core/scene.hpp"
#include "sweep/profile.hpp"
#include "sweep/study/loader.hpp"

namespace rodend::study_detail {

std::unique_ptr<Scene> build_checked(const std::string& scene, const ParameterSet& params) {
  try {
    return make_scene(scene, params);
  } catch (const InputError& e) {
    if (e.key_path() == "scene") throw;
    throw e.located("", "parameters");
  }
}

namespace {

/// Each axis's position for case `index` (last axis fastest) and the case's scene.
std::vector<std::size_t> grid_position(const Grid& g, std::size_t index, std::size_t& which) {
  std::size_t rest = index;
  std::vector<std::size_t> pos(g.axes.size());
  for (std::size_t a = g.axes.size(); a-- > 0;) {
    pos[a] = rest % g.axes[a].size();
    rest /= g.axes[a].size();
  }
  which = 0;  // the case's scene, an index into g.scenes
  if (g.scene_axis.axis >= 0) {
    const auto sa = static_cast<std::size_t>(g.scene_axis.axis);
    const std::string& name =
        g.axes[sa].values[g.scene_axis.member][pos[sa]].get_ref<const std::string&>();
    which = static_cast<std::size_t>(std::find(g.scenes.begin(), g.scenes.end(), name) -
                                     g.scenes.begin());
  }
  return pos;
}

/// The checks that interact between axes: integrator and time settings, history size, the
/// scene's own checks, a wear evolution's needs.
void check_case(const Draft& d, const std::vector<SignalId>& signals) {
  validate(d.integrator);
  validate(d.time);
  check_history_size(d.time, signals);
  const auto scene = build_checked(d.scene, d.parameters);
  check_sensors(d.sensors, *scene);
  if (d.wear_evolution.enabled && !scene->features().has(Feature::wear))
    throw InputError("parameters.wear.model",
                     "a wear_evolution study needs a scene with a wear model and "
                     "wear.model \"archard\"");
  if (d.wear_evolution.enabled && d.wear_evolution.clearance_limit == 0.0 &&
      d.wear_evolution.backlash_limit == 0.0 && d.wear_evolution.max_cycles >= 1e8)
    throw InputError("wear_evolution",
                     "needs a clearance_limit, a backlash_limit or a max_cycles below "
                     "1e8 to stop at");
}

/// " (grid case N: {coordinates})" after the error of a case, "design case" in a study with a
/// sampled design, then what the axis of the key in error says of it (a design factor's
/// distribution).
std::string case_context(const Grid& g, std::size_t index, const Json& coordinates,
                         const std::string& key) {
  const bool design = g.axes.back().keys.front() == "design.sample";
  std::string s = std::string(design ? " (design case " : " (grid case ") + std::to_string(index) +
                  ": " + coordinates.dump() + ")";
  for (const Axis& a : g.axes)
    for (std::size_t k = 0; k < a.keys.size() && k < a.hints.size(); ++k)
      if (a.keys[k] == key && !a.hints[k].empty()) s += "; " + a.hints[k];
  return s;
}

/// The case of draft `d` (of the grid's scene `which`; its parameters moved out), but its
/// index, coordinates and id.
void fill_case(const Grid& g, Draft& d, std::size_t which, CaseSpec& c) {
  c.scene = d.scene;
  c.parameters = std::move(d.parameters);
  c.integrator = d.integrator;
  c.time = d.time;
  c.health = d.health;
  c.metrics = d.metrics;
  c.wear_evolution = d.wear_evolution;
  c.sensors = d.sensors;
  c.signals = g.scene_signals[which];
  c.output = g.output;
}

/// Case `index` of the grid; `check`: the per-case validation and the id from the canonical
/// form (else the id stored by the validation pass).
CaseSpec resolve_case(const Grid& g, std::size_t index, bool check) {
  CaseSpec c;
  std::size_t which = 0;
  const std::vector<std::size_t> pos = grid_position(g, index, which);
  Draft d = g.bases[which];
  try {
    for (std::size_t a = 0; a < g.axes.size(); ++a)
      for (std::size_t k = 0; k < g.axes[a].keys.size(); ++k) {
        const std::string& key = g.axes[a].keys[k];
        const Json& v = g.axes[a].values[k][pos[a]];
        c.coordinates[key] = v;
        if (key == "scene") continue;  // chosen above
        if (key == "design.sample")
          c.design_sample = v.get<long>();
        else
          apply(d, key, v, g.origins.of_axis(g.axes[a].wheres[k]));
      }
    if (g.profiles_possible) attach_profiles(d.parameters, *g.profiles);
    if (g.profiles_possible && check) check_profiles_cover(d.parameters, d.time.end);
    if (check) check_case(d, g.scene_signals[which]);
  } catch (const InputError& e) {
    if (g.axes.empty()) throw;
    throw InputError(e.key_path(),
                     e.problem() + case_context(g, index, c.coordinates, e.key_path()));
  }
  c.index = static_cast<long>(index);
  fill_case(g, d, which, c);
  if (check) {
    c.id = case_id(c);
  } else {
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(g.ids[index]));
    c.id = buf;
  }
  return c;
}

/// The id of case `index`, checked as resolve_case checks it, for a grid with an id template:
/// `d`, the thread's copy of the base draft, takes the case's values (every axis sets the same
/// keys in every case, so nothing of the previous case is left) instead of a fresh copy of the
/// base and its parameters for each case, and the id comes from the template instead of the
/// case's canonical form. A case that fails is resolved again the usual way, for its message.
std::uint64_t checked_id(const Grid& g, const IdTemplate& t, std::size_t index,
                         std::optional<Draft>& d) {
  if (!d) d = g.bases[0];
  std::size_t which = 0;
  const std::vector<std::size_t> pos = grid_position(g, index, which);
  try {
    for (std::size_t a = 0; a < g.axes.size(); ++a)
      for (std::size_t k = 0; k < g.axes[a].keys.size(); ++k)
        if (g.axes[a].keys[k] != "design.sample")
          apply(*d, g.axes[a].keys[k], g.axes[a].values[k][pos[a]],
                g.origins.of_axis(g.axes[a].wheres[k]));
    check_case(*d, g.scene_signals[0]);
  } catch (const InputError&) {
    d.reset();
    resolve_case(g, index, true);  // throws the error, with the case's coordinates
    throw;
  }
  return t.id(g, pos);
}

/// The id template of the grid, when it has one (IdTemplate::of).
std::optional<IdTemplate> id_template(const Grid& g) {
  if (g.profiles_possible || g.bases.size() != 1) return std::nullopt;
  Draft d = g.bases[0];
  CaseSpec base;
  fill_case(g, d, 0, base);
  return IdTemplate::of(g, base);
}

/// Every case resolved and checked once, its id kept: over the cores for a large study (the
/// cases are independent; each costs about 0.16 ms, mostly its scene's own checks and its id;
/// with an id template, about a fifth of that). The error of the lowest failing case is the one
/// reported, as a pass in order would.
void validate_cases(Grid& grid, std::size_t total) {
  constexpr std::size_t kParallelFrom = 4096;  // below, a thread team costs more than it saves
  grid.ids.assign(total, 0);
  const std::optional<IdTemplate> fast = id_template(grid);
  std::size_t first_bad = total;
  std::exception_ptr error;
  std::mutex mutex;
  const auto n = static_cast<std::ptrdiff_t>(total);
#pragma omp parallel if (total >= kParallelFrom)
  {
    std::optional<Draft> scratch;  // the thread's copy of the base (checked_id)
#pragma omp for schedule(dynamic, 256)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      const auto index = static_cast<std::size_t>(i);
      {
        const std::lock_guard lock(mutex);
        if (index > first_bad) continue;  // a lower case failed: its error is the one reported
      }
      try {
        grid.ids[index] = fast ? checked_id(grid, *fast, index, scratch)
                               : std::stoull(resolve_case(grid, index, true).id, nullptr, 16);
      } catch (...) {
        const std::lock_guard lock(mutex);
        if (index < first_bad) {
          first_bad = index;
          error = std::current_exception();
        }
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace

CaseList index_cases(std::shared_ptr<Grid> grid, std::size_t total) {
  validate_cases(*grid, total);
  std::vector<std::uint64_t> ids = grid->ids;
  std::sort(ids.begin(), ids.end());
  if (std::adjacent_find(ids.begin(), ids.end()) != ids.end())
    throw InputError("grid", "two grid points resolve to the same case (a repeated value?)");
  const std::shared_ptr<const Grid> frozen = grid;
  CaseList cases(total, std::make_shared<const CaseList::Resolver>([frozen](std::size_t i) {
                   if (i >= frozen->ids.size())
                     throw std::out_of_range("case index " + std::to_string(i));
                   return resolve_case(*frozen, i, false);
                 }));
  const bool light = std::none_of(frozen->axes.begin(), frozen->axes.end(), [](const Axis& a) {
    return std::any_of(a.keys.begin(), a.keys.end(), [](const std::string& k) {
      return k.rfind("integrator.", 0) == 0 || k.rfind("time.", 0) == 0;
    });
  });
  if (light)
    cases.set_rows(std::make_shared<const CaseList::RowResolver>([frozen](std::size_t i) {
      std::size_t which = 0;
      const std::vector<std::size_t> pos = grid_position(*frozen, i, which);
      CaseList::Row r;
      r.index = static_cast<long>(i);
      char buf[17];
      std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(frozen->ids.at(i)));
      r.id = buf;
      r.method = frozen->bases[which].integrator.method;
      r.end_s = frozen->bases[which].time.end;
      r.coordinates = Json::object();
      for (std::size_t a = 0; a < frozen->axes.size(); ++a)
        for (std::size_t k = 0; k < frozen->axes[a].keys.size(); ++k)
          r.coordinates[frozen->axes[a].keys[k]] = frozen->axes[a].values[k][pos[a]];
      return r;
    }));
  return cases;
}

}  // namespace rodend::study_detail
