// Reading the parts every scene shares (bodies, the contact, springs, loads) from parameters,
// with the physical checks that go with them. Each throws InputError naming the key path.
#pragma once

#include <string>

#include "core/contact.hpp"
#include "core/params.hpp"
#include "core/rigid_body.hpp"
#include "core/scene.hpp"
#include "core/scenes/signal_groups.hpp"
#include "core/spring3d.hpp"

namespace rodend {

/// `<prefix>.mass` [kg] > 0 and `<prefix>.inertia` [kg m^2] (3 principal moments) > 0.
RigidBodyParams read_body(const ParameterSet& p, const std::string& prefix);

/// The clearance contact under `<prefix>` (geometry, clearance, ball_radius, bearing_length,
/// materials, stiffness_scale, law, restitution, min_impact_speed) and the friction under
/// `<friction_prefix>`. `geometry` "sphere" (Hertz, ball in a conformal socket) or "cylinder"
/// (pin in a bearing of length `bearing_length`, read only then). The clearance is read from
/// `clearance_path` when given (scenes with several joints sharing one contact block), else
/// from `<prefix>.clearance`. `holds_stick`: the scene computes the force of a stuck contact
/// (core/contact_stick.hpp), so friction.mode switch is accepted (else an InputError).
ClearanceContactModel read_clearance_contact(const ParameterSet& p, const std::string& prefix,
                                             const std::string& friction_prefix,
                                             const std::string& clearance_path = {},
                                             bool holds_stick = false);

/// A 3-D spring under `<prefix>` (stiffness, damping, rotational_stiffness, rotational_damping),
/// all >= 0.
Spring3DParams read_spring(const ParameterSet& p, const std::string& prefix);

/// A number for an error message (6 significant digits).
std::string format_number(double v);

/// A number that must be > 0 (or >= 0 with allow_zero).
double read_positive(const ParameterSet& p, const std::string& path, bool allow_zero = false);

/// A choice of a catalogue (core/choice.hpp) named by the text at `path`; an unknown name is an
/// InputError naming the key path, listing the catalogue's names and the nearest one
/// (choice_expected). The one reader of a menu's name in a parameter set.
template <Choice E>
E read_choice(const ParameterSet& p, const std::string& path) {
  const std::string name = p.text(path);
  if (const auto e = choice_from_name<E>(name)) return *e;
  throw InputError(path, choice_expected<E>(name));
}

}  // namespace rodend

namespace rodend {

/// Writes the energy-audit signals, kEnergySignals (signal_groups.hpp), from the terms at t and
/// the mechanical energy at t = 0.
void write_energy_signals(SignalFrame& frame, const EnergyTerms& e, double initial_mechanical);

/// | |q| - 1 | of the raw (unnormalised) quaternion stored at x[offset..offset+3].
double quaternion_norm_error(const double* x, int offset);

/// Writes one body's 13 state scales (its share of Scene::state_scale) at s[0..12]: `length` [m]
/// for the position, `speed` [m/s] for the velocity, `angular_rate` [rad/s] for the angular
/// velocity and 1 for the unit quaternion (BodyStateLayout).
void body_state_scale(double* s, double length, double speed, double angular_rate);

/// A scene with one clearance contact (the ball in its socket): contact_count, contact_clearance
/// and contact_radius of the ClearanceContactModel that `Derived::contact()` returns.
template <class Derived>
class OneContactScene : public Scene {
 public:
  int contact_count() const override { return 1; }
  double contact_clearance(int) const override { return model().clearance; }
  double contact_radius(int) const override { return model().ball_radius; }

 private:
  const ClearanceContactModel& model() const {
    return static_cast<const Derived&>(*this).contact();
  }
};

/// Writes the contact signals, kContactSignals (signal_groups.hpp): eccentricity, penetration,
/// forces, slip, wear indicator, ...
void write_contact_signals(SignalFrame& f, const ContactEval& c, const BodyKinematics& ball,
                           const BodyKinematics& socket, const ContactLatch& latch);

}  // namespace rodend
