// Hunt-Crossley: chi = 3(1 - c_r)/2 (model-notes §3).
#include "core/contact.hpp"

namespace rodend {
namespace {
class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "hunt-crossley"; }
  std::string_view description() const override {
    return "Hunt-Crossley: chi = 3(1 - c_r)/2 (model-notes §3)";
  }
  double hysteresis_factor(double cr) const override { return 1.5 * (1.0 - cr); }
  bool defined_at_zero_restitution() const override { return true; }
};
}  // namespace

const NormalLaw& hunt_crossley_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
