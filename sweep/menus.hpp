// Every menu of the program: the core's (core/menus.def) and the batch runner's
// (sweep/menus.def), for `rodend choices` and docs/choices.md.
#pragma once

#include <span>

#include "core/menus.hpp"

namespace rodend {

/// core_menus() then the menus of sweep/menus.def.
std::span<const Menu> all_menus();

}  // namespace rodend
