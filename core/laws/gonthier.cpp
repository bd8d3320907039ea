// Gonthier et al.: chi = (1 - c_r^2)/c_r (model-notes §3). Undefined at c_r = 0.
#include "core/contact.hpp"

namespace rodend {
namespace {
class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "gonthier"; }
  std::string_view description() const override {
    return "Gonthier et al.: chi = (1 - c_r^2)/c_r (model-notes §3); undefined at c_r = 0";
  }
  double hysteresis_factor(double cr) const override { return (1.0 - cr * cr) / cr; }
  bool defined_at_zero_restitution() const override { return false; }
};
}  // namespace

const NormalLaw& gonthier_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
