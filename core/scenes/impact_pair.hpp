// Scene impact-pair's menu: the outer body fixed to ground or free (impact.outer_body,
// core/scenes/outer_bodies.def), for the scene and the catalogue of menus (core/menus.def).
#pragma once

#include "core/choice.hpp"

namespace rodend {

#define RODEND_CHOICE_ENUM OuterBody
#define RODEND_CHOICE_FILE "core/scenes/outer_bodies.def"
#include "core/choice.hpp"

}  // namespace rodend
