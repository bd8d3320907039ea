// Hertz, purely elastic: chi = 0 (thesis 3.3). Restitution is ignored.
#include "core/contact.hpp"

namespace rodend {
namespace {
class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "hertz"; }
  std::string_view description() const override {
    return "Hertz, purely elastic: chi = 0 (thesis 3.3); the restitution is ignored";
  }
  double hysteresis_factor(double cr) const override { return 0.0 * cr; }
  bool defined_at_zero_restitution() const override { return true; }
};
}  // namespace

const NormalLaw& hertz_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
