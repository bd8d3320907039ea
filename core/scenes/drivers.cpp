#include "core/scenes/drivers.hpp"

#include <memory>

#include "core/scenes/input_kinds.hpp"

namespace rodend {

// Each menu's lines name the class of their kind: RODEND_CHOICE(enumerator, "name",
// "description", Class).
#define RODEND_CHOICE(identifier, name, description, Class) \
  case Kind::identifier:                                    \
    return Class::read(in);

InputPtr make_input(WaveformKind kind, const InputKeys& in) {
  using Kind = WaveformKind;
  switch (kind) {
#include "core/scenes/waveforms.def"
  }
  throw InputError(in.prefix, "unknown waveform");
}

InputPtr make_input(MotionShape kind, const InputKeys& in) {
  using Kind = MotionShape;
  switch (kind) {
#include "core/scenes/motion_shapes.def"
  }
  throw InputError(in.prefix, "unknown motion shape");
}

InputPtr make_input(HingeMomentKind kind, const InputKeys& in) {
  using Kind = HingeMomentKind;
  switch (kind) {
#include "core/scenes/hinge_moments.def"
  }
  throw InputError(in.prefix, "unknown hinge moment");
}

InputPtr make_input(LoadKind kind, const InputKeys& in) {
  using Kind = LoadKind;
  switch (kind) {
#include "core/scenes/load_kinds.def"
  }
  throw InputError(in.prefix, "unknown load kind");
}

#undef RODEND_CHOICE

InputPtr read_motion(const ParameterSet& p, const std::string& prefix) {
  return read_input<MotionShape>(p, prefix, "shape");
}

InputPtr read_hinge(const ParameterSet& p, const std::string& prefix) {
  InputPtr kind = read_input<HingeMomentKind>(p, prefix, "kind");
  const double a = p.number(prefix + ".sine_amplitude");
  const double f = read_positive(p, prefix + ".sine_frequency", true);
  if (a == 0.0) return kind;
  return std::make_shared<SumInput>(std::make_shared<SinusoidInput>(a, f), std::move(kind));
}

Load read_load(const ParameterSet& p, const std::string& prefix) {
  Load l;
  l.shape = read_input<LoadKind>(p, prefix, "kind", true);
  l.amplitude = p.vec3(prefix + ".amplitude");
  l.body_frame = read_choice<LoadFrame>(p, prefix + ".frame") == LoadFrame::body;
  return l;
}

}  // namespace rodend
