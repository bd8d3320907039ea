// Friction laws: mu(|v_t|) in F_t = -mu F_n v_t/|v_t|.
#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "core/contact.hpp"

namespace rodend {
namespace {

/// The thesis's empirical law (thesis 3.9-3.10, model-notes §2): mu rises from 0 at zero slip
/// to mu_st at v_st along the cubic step centred on 0, blends to mu_dyn at v_dyn, plus a
/// viscous term mu_v v.
class ThesisFriction final : public FrictionLaw {
 public:
  explicit ThesisFriction(const FrictionParams& p) : p_(p) {}
  std::string_view name() const override { return "thesis"; }
  double coefficient(double v) const override {
    const Blend b = blend(v);
    return smooth_step(v, b.v0, b.y0, b.v1, b.y1) + p_.viscous_coefficient * v;
  }
  double slope(double v) const override {
    const Blend b = blend(v);
    return smooth_step_slope(v, b.v0, b.y0, b.v1, b.y1) + p_.viscous_coefficient;
  }

 private:
  /// The cubic step that holds at slip speed v, (v0, y0) to (v1, y1), its levels less the
  /// viscous term's: the rise centred on zero slip up to v_st, or the blend to v_dyn.
  struct Blend {
    double v0, y0, v1, y1;
  };
  Blend blend(double v) const {
    const double st = p_.static_coefficient - p_.viscous_coefficient * p_.static_speed;
    const double dyn = p_.dynamic_coefficient - p_.viscous_coefficient * p_.dynamic_speed;
    if (v <= p_.static_speed) return {-p_.static_speed, -st, p_.static_speed, st};
    return {p_.static_speed, st, p_.dynamic_speed, dyn};
  }

  FrictionParams p_;
};

/// Ambrosio's law (model-notes §2): mu = c_f c_d, c_d ramping linearly from 0 at v0 to 1 at v1.
class AmbrosioFriction final : public FrictionLaw {
 public:
  explicit AmbrosioFriction(const FrictionParams& p) : p_(p) {}
  std::string_view name() const override { return "ambrosio"; }
  double coefficient(double v) const override {
    const double v0 = p_.static_speed, v1 = p_.dynamic_speed;
    const double cd = v <= v0 ? 0.0 : (v >= v1 ? 1.0 : (v - v0) / (v1 - v0));
    return p_.dynamic_coefficient * cd;
  }
  double slope(double v) const override {
    const double v0 = p_.static_speed, v1 = p_.dynamic_speed;
    return v <= v0 || v >= v1 ? 0.0 : p_.dynamic_coefficient / (v1 - v0);
  }

 private:
  FrictionParams p_;
};

/// Regularised Coulomb: mu = mu_dyn tanh(v / v_eps), v_eps = static_speed.
class CoulombFriction final : public FrictionLaw {
 public:
  explicit CoulombFriction(const FrictionParams& p) : p_(p) {}
  std::string_view name() const override { return "coulomb"; }
  double coefficient(double v) const override {
    return p_.dynamic_coefficient * std::tanh(v / p_.static_speed);
  }
  double slope(double v) const override {
    const double t = std::tanh(v / p_.static_speed);
    return p_.dynamic_coefficient * (1.0 - t * t) / p_.static_speed;
  }

 private:
  FrictionParams p_;
};

/// A law held at its value at `cap_speed` where it lies on the wrong side of it: `below` true,
/// mu <= law(v_dyn) below v_dyn, where the law exceeds it (the slipping branch of friction.mode
/// stick-slip, contact.hpp, make_friction_branches); `below` false, mu >= law(v) beyond v.
class CappedBranch final : public FrictionLaw {
 public:
  CappedBranch(std::shared_ptr<const FrictionLaw> law, double cap_speed, bool below)
      : law_(std::move(law)),
        speed_(cap_speed),
        cap_(law_->coefficient(cap_speed)),
        below_(below) {}
  std::string_view name() const override { return law_->name(); }
  double coefficient(double v) const override {
    const double mu = law_->coefficient(v);
    return capped(v, mu) ? cap_ : mu;
  }
  double slope(double v) const override {
    return capped(v, law_->coefficient(v)) ? 0.0 : law_->slope(v);
  }

 private:
  /// stuck (below_ false): beyond v_st where the law fell under its peak; slipping (below_
  /// true): below v_dyn where the law is above its value at v_dyn
  bool capped(double v, double mu) const {
    return below_ ? v < speed_ && mu > cap_ : v > speed_ && mu < cap_;
  }

  std::shared_ptr<const FrictionLaw> law_;
  double speed_, cap_;
  bool below_;
};

std::unique_ptr<FrictionLaw> make_thesis_friction(const FrictionParams& p) {
  return std::make_unique<ThesisFriction>(p);
}
std::unique_ptr<FrictionLaw> make_ambrosio_friction(const FrictionParams& p) {
  return std::make_unique<AmbrosioFriction>(p);
}
std::unique_ptr<FrictionLaw> make_coulomb_friction(const FrictionParams& p) {
  return std::make_unique<CoulombFriction>(p);
}
std::unique_ptr<FrictionLaw> make_no_friction(const FrictionParams&) {
  return nullptr;
}

using Maker = std::unique_ptr<FrictionLaw> (*)(const FrictionParams&);
struct Entry {
  Maker make;
  bool ordered_speeds;
};
constexpr Entry kLaws[] = {
#define RODEND_CHOICE(identifier, name, description, maker, ordered_speeds) \
  {&maker, ordered_speeds},
#include "core/laws/friction_laws.def"
#undef RODEND_CHOICE
};

}  // namespace

bool needs_ordered_speeds(FrictionLawKind law) {
  return kLaws[static_cast<std::size_t>(law)].ordered_speeds;
}

std::unique_ptr<FrictionLaw> make_friction_law(const FrictionParams& p) {
  return kLaws[static_cast<std::size_t>(p.law)].make(p);
}

FrictionBranches make_friction_branches(std::shared_ptr<const FrictionLaw> law,
                                        const FrictionParams& p) {
  if (!law || !(law->coefficient(p.static_speed) > law->coefficient(p.dynamic_speed))) return {};
  return {law, std::make_shared<CappedBranch>(law, p.dynamic_speed, true)};
}

void set_friction_mode(ClearanceContactModel& m, FrictionMode mode, const FrictionParams& p) {
  if (mode == FrictionMode::smooth) return;
  m.branches = make_friction_branches(m.friction, p);
  m.switch_speed = p.static_speed;
  if (mode == FrictionMode::switch_model && m.friction) {
    m.stick = true;
    m.static_limit =
        std::max(m.friction->coefficient(p.static_speed), m.friction->coefficient(p.dynamic_speed));
  }
}

}  // namespace rodend
