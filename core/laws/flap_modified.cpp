// The flap-actuation study's "modified law" (model-notes §3): chi = (1 - c_r^2)/c_r, the
// Gonthier et al. hysteresis factor, meant for the cylinder-in-cylinder geometry
// (contact.geometry = "cylinder": F_el = (pi/2) L E* delta^1.5 (2 (dR + delta))^(-1/2)).
// The law itself supplies chi only, like every law: the geometry is chosen separately, so on a
// sphere it is Gonthier's law under another name. Undefined at c_r = 0.
#include "core/contact.hpp"

namespace rodend {
namespace {
class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "flap-modified"; }
  std::string_view description() const override {
    return "the flap-actuation study's modified law: Gonthier's chi, meant for contact.geometry "
           "cylinder (model-notes §3)";
  }
  double hysteresis_factor(double cr) const override { return (1.0 - cr * cr) / cr; }
  bool defined_at_zero_restitution() const override { return false; }
};
}  // namespace

const NormalLaw& flap_modified_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
