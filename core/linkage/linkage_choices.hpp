// The planar linkage's menus (core/choice.hpp): the kinds of body and the types of joint a part
// file names (linkage.bodies.<name>.kind, linkage.joints.<name>.type), and its drives
// (linkage.actuator.kind). A joint's model (ideal or clearance: a revolute joint's radial
// clearance, a prismatic guide's play) is the slider-crank's menu, JointModel
// (core/scenes/planar_slider_crank_options.hpp).
#pragma once

#include "core/choice.hpp"

namespace rodend {
#define RODEND_CHOICE_ENUM BodyKind
#define RODEND_CHOICE_FILE "core/linkage/body_kinds.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM JointType
#define RODEND_CHOICE_FILE "core/linkage/joint_types.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM LinkageDrive
#define RODEND_CHOICE_FILE "core/linkage/drive_kinds.def"
#include "core/choice.hpp"
}  // namespace rodend
