// Flores et al.: chi = 8(1 - c_r)/(5 c_r) (model-notes §3). Undefined at c_r = 0.
#include "core/contact.hpp"

namespace rodend {
namespace {
class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "flores"; }
  std::string_view description() const override {
    return "Flores et al.: chi = 8(1 - c_r)/(5 c_r) (model-notes §3); undefined at c_r = 0";
  }
  double hysteresis_factor(double cr) const override { return 1.6 * (1.0 - cr) / cr; }
  bool defined_at_zero_restitution() const override { return false; }
};
}  // namespace

const NormalLaw& flores_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
