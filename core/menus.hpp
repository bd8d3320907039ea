// The catalogue of menus: every set of named choices the program offers, one line each in
// core/menus.def (the core's) and sweep/menus.def (the batch runner's). `rodend choices` and
// docs/choices.md list them all, and a parameter leaf names one as its "catalogue" (core
// scene files, core/scene_parameters.hpp). A menu's names and descriptions come from its own
// catalogue: an enum's .def (core/choice.hpp) or a registry of classes (the normal laws).
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/choice.hpp"

namespace rodend {

/// One choice of a menu, as the edges show it.
struct MenuItem {
  std::string name;
  std::string description;
};

/// A menu: its catalogue name (what a parameter leaf's "catalogue" names), a title, the key
/// paths that take its names, and its choices in order.
struct Menu {
  std::string_view id;
  std::string_view title;
  std::string_view keys;
  std::vector<MenuItem> (*items)();
};

/// The choices of an enum's catalogue (core/choice.hpp) as menu items.
template <Choice E>
std::vector<MenuItem> choice_items() {
  const auto names = choice_names(E{});
  const auto descriptions = choice_descriptions(E{});
  std::vector<MenuItem> out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out.push_back({std::string(names[i]), std::string(descriptions[i])});
  return out;
}

/// The menus of core/menus.def, in its order.
std::span<const Menu> core_menus();
/// The menu called `id` in `menus`, or nullptr.
const Menu* find_menu(std::span<const Menu> menus, std::string_view id);
/// A menu's names, in order.
std::vector<std::string> menu_names(const Menu& menu);

}  // namespace rodend
