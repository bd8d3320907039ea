// Lankarani-Nikravesh: chi = 3(1 - c_r^2)/4 (thesis 3.8; model-notes §1). The thesis's law.
#include "core/contact.hpp"

namespace rodend {
namespace {
class Law final : public NormalLaw {
 public:
  std::string_view name() const override { return "lankarani-nikravesh"; }
  std::string_view description() const override {
    return "Lankarani-Nikravesh: chi = 3(1 - c_r^2)/4 (thesis 3.8), the thesis's law";
  }
  double hysteresis_factor(double cr) const override { return 0.75 * (1.0 - cr * cr); }
  bool defined_at_zero_restitution() const override { return true; }
};
}  // namespace

const NormalLaw& lankarani_nikravesh_law() {
  static const Law law;
  return law;
}

}  // namespace rodend
