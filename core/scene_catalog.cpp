// The scene catalogue, built from scenes/scenes.def.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/scene.hpp"
#include "core/scene_parameters.hpp"

namespace rodend {

ContactSnapshot Scene::contact_snapshot(int, double t, const double* x,
                                        const DiscreteState& d) const {
  SignalFrame f;
  outputs(t, x, d, f);
  return {f.get(SignalId::penetration), f.get(SignalId::penetration_rate),
          f.get(SignalId::eccentricity), f.get(SignalId::contact_force)};
}

void Scene::jacobian(double t, const double* x, const DiscreteState& d, double* J) const {
  // Forward differences with the increment sqrt(eps) times the state's scale (its
  // characteristic magnitude), not times |x_j|: a body's position is ~0.3 m while the contact
  // sees its relative position at the penetration's scale, ~1e-7 m; sqrt(eps) |x_j| (4e-9 m)
  // is then no longer small against the Hertz law's curvature (its derivatives grow as
  // delta^(-1/2)), and that error in J cut rosenbrock4 to first order in sustained contact
  // (local error O(h^2), measured on rod-end-kinematic at t = 0.2 s: 5.8e-6 at h = 1e-4 s
  // against 1.5e-8 with a Jacobian accurate to second order). sqrt(eps) scale (7.5e-12 m on
  // the 0.5 mm clearance scale) keeps truncation ~h / delta ~ 1e-4 and round-off
  // ~eps |x_j| / h ~ 1e-5. Columns of the audit states are zero (bookkeeping integrals: nothing
  // reads them), so they cost no call.
  const int n = state_size();
  const auto un = static_cast<std::size_t>(n);
  std::vector<double> scale(un), xp(x, x + n), f0(un), fp(un);
  state_scale(scale.data());
  std::vector<bool> audit(un, false);
  for (int o : audit_offsets()) audit[static_cast<std::size_t>(o)] = true;
  derivatives(t, x, d, f0.data());
  const double eps = std::sqrt(std::numeric_limits<double>::epsilon());
  for (std::size_t j = 0; j < un; ++j) {
    if (audit[j]) {
      for (std::size_t i = 0; i < un; ++i) J[i * un + j] = 0.0;
      continue;
    }
    const double h = eps * std::abs(scale[j]);
    xp[j] = x[j] + h;
    const double hp = xp[j] - x[j];  // the increment actually represented
    derivatives(t, xp.data(), d, fp.data());
    xp[j] = x[j];
    for (std::size_t i = 0; i < un; ++i) J[i * un + j] = (fp[i] - f0[i]) / hp;
  }
}

int Scene::jacobian_cost() const {
  return state_size() + 1 - static_cast<int>(audit_offsets().size());
}

#define RODEND_SCENE(name, fn, doc) std::unique_ptr<Scene> fn(const ParameterSet&);
#include "core/scenes/scenes.def"
#undef RODEND_SCENE

// generated at configure time from core/scenes/*.params.json
std::string_view embedded_scene_defaults(std::string_view scene);

std::span<const SceneEntry> scene_catalogue() {
  static const std::array kScenes{
#define RODEND_SCENE(name, fn, doc) SceneEntry{name, &fn, doc},
#include "core/scenes/scenes.def"
#undef RODEND_SCENE
  };
  return kScenes;
}

const SceneEntry* find_scene(std::string_view name) {
  for (const SceneEntry& s : scene_catalogue())
    if (s.name == name) return &s;
  return nullptr;
}

static std::string known_scenes() {
  std::string s;
  for (const SceneEntry& e : scene_catalogue()) s += (s.empty() ? "" : ", ") + std::string(e.name);
  return s;
}

std::string_view scene_default_parameters_json(std::string_view scene) {
  if (!find_scene(scene))
    throw InputError(
        "scene", "unknown scene '" + std::string(scene) + "'; expected one of: " + known_scenes());
  return embedded_scene_defaults(scene);
}

ParameterSet ParameterSet::defaults_for(std::string_view scene) {
  const std::string file = std::string(scene) + ".params.json";
  const Json doc = Json::parse(scene_default_parameters_json(scene));
  return from_json(compose_scene_parameters(doc, file), file);
}

namespace {
// the scene a SceneFactoryOverride builds instead, and its factory
struct FactoryOverride {
  std::string name;
  SceneFactory make;
};
// Installed and removed on the test's thread, read by every worker thread that makes a scene:
// an atomic pointer to an object that does not change while it is installed (the release
// store publishes its fields to the acquire load), so no worker reads a half-written name.
std::atomic<const FactoryOverride*> g_override{nullptr};
}  // namespace

std::unique_ptr<Scene> make_scene(std::string_view name, const ParameterSet& params) {
  const SceneEntry* e = find_scene(name);
  if (!e)
    throw InputError(
        "scene", "unknown scene '" + std::string(name) + "'; expected one of: " + known_scenes());
  if (const FactoryOverride* o = g_override.load(std::memory_order_acquire); o && name == o->name)
    return o->make(params);
  return e->make(params);
}

SceneFactoryOverride::SceneFactoryOverride(std::string_view name, SceneFactory make) {
  auto* o = new FactoryOverride{std::string(name), make};
  const FactoryOverride* none = nullptr;
  if (!g_override.compare_exchange_strong(none, o, std::memory_order_acq_rel)) {
    delete o;
    throw std::logic_error("a SceneFactoryOverride is already in place");
  }
}

SceneFactoryOverride::~SceneFactoryOverride() {
  delete g_override.exchange(nullptr, std::memory_order_acq_rel);
}

}  // namespace rodend
