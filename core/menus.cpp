// The catalogue of menus, built from core/menus.def.
#include "core/menus.hpp"

#include "core/contact.hpp"
#include "core/integrator.hpp"
#include "core/linkage/beam_modes.hpp"
#include "core/linkage/linkage_choices.hpp"
#include "core/params.hpp"
#include "core/presets.hpp"
#include "core/scene.hpp"
#include "core/scenes/drivers.hpp"
#include "core/scenes/impact_pair.hpp"
#include "core/scenes/parts.hpp"
#include "core/scenes/planar_slider_crank_options.hpp"
#include "core/scenes/profile.hpp"
#include "core/scenes/servo_actuator.hpp"
#include "core/wear.hpp"

namespace rodend {
namespace {

/// The scenes (core/scenes/scenes.def) with their summaries.
std::vector<MenuItem> scene_items() {
  std::vector<MenuItem> out;
  for (const SceneEntry& s : scene_catalogue())
    out.push_back({std::string(s.name), std::string(s.summary)});
  return out;
}

/// The normal-contact laws (core/laws/normal_laws.def), each a class with its name.
std::vector<MenuItem> normal_law_items() {
  std::vector<MenuItem> out;
  for (const NormalLaw* law : normal_laws())
    out.push_back({std::string(law->name()), std::string(law->description())});
  return out;
}

constexpr Menu kMenus[] = {
#define RODEND_MENU(id, title, keys, items) {#id, title, keys, &items},
#include "core/menus.def"
#undef RODEND_MENU
};

}  // namespace

std::span<const Menu> core_menus() {
  return kMenus;
}

const Menu* find_menu(std::span<const Menu> menus, std::string_view id) {
  for (const Menu& m : menus)
    if (m.id == id) return &m;
  return nullptr;
}

std::vector<std::string> menu_names(const Menu& menu) {
  std::vector<std::string> out;
  for (const MenuItem& i : menu.items()) out.push_back(i.name);
  return out;
}

}  // namespace rodend
