// The inputs of the scenes by their menus (core/scenes/input.hpp, one class per kind in
// core/scenes/input_kinds.hpp): the position command (prescribed in rod-end-kinematic, the
// actuator's command in rod-end-actuator, servo-actuator and planar-linkage), the hinge moment,
// and the free body's force and moment.
#pragma once

#include <string>
#include <string_view>

#include "core/choice.hpp"
#include "core/params.hpp"
#include "core/scenes/input.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {

/// The menus of the inputs (core/choice.hpp), each line naming its kind's class: the waveforms
/// (core/scenes/waveforms.def), which the three others include, so that one line adds a waveform
/// to the command (motion.shape, core/scenes/motion_shapes.def), the hinge moment (hinge.kind,
/// core/scenes/hinge_moments.def) and the free body's loads (force.kind, moment.kind,
/// core/scenes/load_kinds.def).
#define RODEND_CHOICE_ENUM WaveformKind
#define RODEND_CHOICE_FILE "core/scenes/waveforms.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM MotionShape
#define RODEND_CHOICE_FILE "core/scenes/motion_shapes.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM HingeMomentKind
#define RODEND_CHOICE_FILE "core/scenes/hinge_moments.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM LoadKind
#define RODEND_CHOICE_FILE "core/scenes/load_kinds.def"
#include "core/choice.hpp"
/// The frame a load's amplitude is given in (`<prefix>.frame`).
#define RODEND_CHOICE_ENUM LoadFrame
#define RODEND_CHOICE_FILE "core/scenes/load_frames.def"
#include "core/choice.hpp"

/// The input of kind `kind`, its keys under `in.prefix`: the class that the kind's line of its
/// menu names (its `read`).
InputPtr make_input(WaveformKind kind, const InputKeys& in);
InputPtr make_input(MotionShape kind, const InputKeys& in);
InputPtr make_input(HingeMomentKind kind, const InputKeys& in);
InputPtr make_input(LoadKind kind, const InputKeys& in);

/// The one reader of an input: the kind named at `<prefix>.<selector>` (a name of the menu E),
/// made from the keys under `<prefix>` it reads (InputKeys::unit: see there). Throws InputError
/// naming the key.
template <Choice E>
InputPtr read_input(const ParameterSet& p, const std::string& prefix, std::string_view selector,
                    bool unit = false) {
  const E kind = read_choice<E>(p, prefix + "." + std::string(selector));
  return make_input(kind, InputKeys{p, prefix, unit});
}

/// The position command or prescribed motion [m]: `<prefix>.shape` (motion_shapes.def) and its
/// keys: a stroke's (extension, retraction, extension_time, retraction_time, hold_time,
/// start_time, cycles), a waveform's (amplitude, offset, start_time, frequency and cycles, or
/// start_frequency, end_frequency and chirp_duration), a profile's (`<prefix>.profile.*`).
InputPtr read_motion(const ParameterSet& p, const std::string& prefix);

/// The hinge moment on the surface [N m], counter-clockwise positive (thesis §6.3.2), of the
/// surface angle theta: `<prefix>.kind` (hinge_moments.def: none; constant, M0 from step_time
/// on; proportional, -k theta; a waveform; a profile) plus the optional sine term
/// sine_amplitude sin(2 pi sine_frequency t).
InputPtr read_hinge(const ParameterSet& p, const std::string& prefix);

/// A vector load [N or N m]: `amplitude` times the input of kind `<prefix>.kind`
/// (load_kinds.def) read with unit amplitude (constant 1, ramp t/T, the waveforms with A = 1
/// and offset 0), in the frame `<prefix>.frame`.
struct Load {
  Vec3 amplitude = Vec3::Zero();
  InputPtr shape;
  bool body_frame = false;  ///< the amplitude is in the body frame (else inertial)
  Vec3 at(double t) const { return amplitude * shape->value(t, 0.0); }
  /// Time integral of at() from 0 to t (for closed forms in tests).
  Vec3 integral(double t) const { return amplitude * shape->integral(t); }
};
Load read_load(const ParameterSet& p, const std::string& prefix);

}  // namespace rodend
