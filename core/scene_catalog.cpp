// The scene catalogue, built from scenes/scenes.def.
#include <array>
#include <stdexcept>
#include <string>

#include "core/scene.hpp"

namespace rodend {

ContactSnapshot Scene::contact_snapshot(int, double t, const double* x,
                                        const DiscreteState& d) const {
  SignalFrame f;
  outputs(t, x, d, f);
  return {f.get(SignalId::penetration), f.get(SignalId::penetration_rate),
          f.get(SignalId::eccentricity), f.get(SignalId::contact_force)};
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

namespace {
// the scene a SceneFactoryOverride builds instead, and its factory (null: none)
std::string g_override_name;
SceneFactory g_override_make = nullptr;
}  // namespace

std::unique_ptr<Scene> make_scene(std::string_view name, const ParameterSet& params) {
  const SceneEntry* e = find_scene(name);
  if (!e)
    throw InputError(
        "scene", "unknown scene '" + std::string(name) + "'; expected one of: " + known_scenes());
  if (g_override_make && name == g_override_name) return g_override_make(params);
  return e->make(params);
}

SceneFactoryOverride::SceneFactoryOverride(std::string_view name, SceneFactory make) {
  if (g_override_make) throw std::logic_error("a SceneFactoryOverride is already in place");
  g_override_name = std::string(name);
  g_override_make = make;
}

SceneFactoryOverride::~SceneFactoryOverride() {
  g_override_make = nullptr;
  g_override_name.clear();
}

}  // namespace rodend
