// The catalogue of normal-contact laws, built from normal_laws.def.
#include <array>

#include "core/contact.hpp"

namespace rodend {

#define RODEND_NORMAL_LAW(fn) const NormalLaw& fn();
#include "core/laws/normal_laws.def"
#undef RODEND_NORMAL_LAW

std::span<const NormalLaw* const> normal_laws() {
  static const std::array kLaws{
#define RODEND_NORMAL_LAW(fn) &fn(),
#include "core/laws/normal_laws.def"
#undef RODEND_NORMAL_LAW
  };
  return kLaws;
}

const NormalLaw* find_normal_law(std::string_view name) {
  for (const NormalLaw* law : normal_laws())
    if (law->name() == name) return law;
  return nullptr;
}

}  // namespace rodend
