// Clearance contact between an inner and an outer body (thesis §3.1; model-notes §1-§3).
//
// The force pipeline, written once for every law and every geometry:
//   penetration delta = |p_ball - p_socket| - c           (thesis 3.1, 3.15)
//   elastic force     F_el(delta), from the geometry of the contact:
//     sphere in sphere      F_el = K delta^n, K = 4/3 E* sqrt(R*)        (Hertz, thesis 3.3)
//     cylinder in cylinder  F_el = (pi/2) L E* delta^n (2 (dR + delta))^(-1/2)
//                           (revolute joint of bearing length L, radial clearance dR = c;
//                            the flap-actuation study's form, model-notes §3)
//   normal force      F_n = max(0, F_el (1 + chi(c_r) * delta' / delta'^-))
//                                                          (law: chi; thesis 3.6-3.8)
// The laws know nothing of the geometry: they supply chi(c_r) only.
// The kinematics are the same for both geometries: delta is read from the distance between the
// two centres, which is the radial penetration of a revolute joint whose pin axis is normal to
// the plane of the relative motion (a planar mechanism; an offset along the pin axis would be
// read as radial).
// delta'^- is the approach speed latched at the onset of a contact episode by the integration
// driver, on an accepted step, never inside the right-hand side. It is guarded from below by
// `min_impact_speed` so chi/delta'^- stays bounded for resting contact.
// The clamp at zero is the single no-pull rule: a contact never pulls (unlike thesis eq. 3.14).
// Optional cap of thesis eq. 3.14 (contact.damping_cap "elastic"): the damping term
// F_el chi delta'/delta'^- is limited from above to the elastic force, F_n = max(0, F_el +
// min(F_el chi delta'/delta'^-, F_el)); still clamped at zero (model-notes §1). Default "none":
// eq. 3.6-3.8 as the laws are calibrated (docs/thesis-deviations.md#eq-3-14-damping-cap).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "core/choice.hpp"
#include "core/math.hpp"
#include "core/rigid_body.hpp"
#include "core/wear.hpp"

namespace rodend {

/// Discrete state of one contact: changes only between accepted steps.
struct ContactLatch {
  bool in_contact = false;    ///< a contact episode is under way
  double impact_speed = 0.0;  ///< approach speed delta'^- latched at onset [m/s]
  bool slipping = false;  ///< friction.mode stick-slip or switch: the slipping branch (else stuck)
};

/// A normal-contact law F = F_el (1 + chi delta'/delta'^-): it supplies chi(c_r).
class NormalLaw {
 public:
  virtual ~NormalLaw() = default;
  virtual std::string_view name() const = 0;
  /// One line for `rodend choices` and docs/choices.md: the law's chi(c_r) and its source.
  virtual std::string_view description() const = 0;
  /// Hysteresis factor chi for the requested restitution coefficient c_r [-].
  virtual double hysteresis_factor(double restitution) const = 0;
  /// Laws that divide by c_r are undefined at c_r = 0 and reject it.
  virtual bool defined_at_zero_restitution() const { return true; }
};

/// Restitution e achieved by a free impact under F = F_el(delta) (1 + chi delta'/delta'^-), for
/// any elastic force F_el (either geometry), mass and approach speed (above min_impact_speed):
/// the root of ln((1 + chi)/(1 - chi e)) = chi (1 + e); 1 at chi = 0. Derivation in
/// core/laws/restitution_matched.cpp.
double free_impact_restitution(double chi);
/// Its inverse: the chi whose free impact restitutes e (0 at e = 1, infinite at e = 0).
double hysteresis_for_restitution(double e);

/// The catalogue of normal laws (core/laws/*.cpp, listed in core/laws/normal_laws.def).
const NormalLaw* find_normal_law(std::string_view name);
std::span<const NormalLaw* const> normal_laws();

/// A friction law: coefficient mu(|v_t|) in F_t = -mu F_n v_t/|v_t| (thesis 3.11).
class FrictionLaw {
 public:
  virtual ~FrictionLaw() = default;
  virtual std::string_view name() const = 0;
  /// Friction coefficient at slip speed `v` >= 0 [m/s]; 0 at v = 0 so the force is continuous.
  virtual double coefficient(double slip_speed) const = 0;
  /// Its derivative d mu / d v at slip speed `v` >= 0 [s/m] (the exact Jacobians; at a join of
  /// two pieces, the slope of the piece coefficient() evaluates there).
  virtual double slope(double slip_speed) const = 0;
};

/// The friction laws (friction.law), from core/laws/friction_laws.def.
#define RODEND_CHOICE_ENUM FrictionLawKind
#define RODEND_CHOICE_FILE "core/laws/friction_laws.def"
#include "core/choice.hpp"
/// Whether the law needs dynamic_speed > static_speed (its catalogue line).
bool needs_ordered_speeds(FrictionLawKind law);

/// How a law is applied (friction.mode), from core/laws/friction_modes.def: smooth (the law as
/// it is), stick-slip (stuck and slipping branches, latched by the driver) or switch (stuck:
/// the force that holds the slip at zero, core/contact_stick.hpp; slipping: the law).
#define RODEND_CHOICE_ENUM FrictionMode
#define RODEND_CHOICE_FILE "core/laws/friction_modes.def"
#include "core/choice.hpp"

/// Parameters shared by the friction laws (each uses the ones it needs).
struct FrictionParams {
  FrictionLawKind law = FrictionLawKind::thesis;  ///< the catalogue's law
  double static_coefficient = 0.0;                ///< mu_st [-] (thesis 3.9)
  double dynamic_coefficient = 0.0;  ///< mu_dyn [-] (thesis 3.9); c_f of Ambrosio; mu of Coulomb
  double static_speed = 1e-3;        ///< v_st [m/s] (thesis 3.9); v0 of Ambrosio; v_eps of Coulomb
  double dynamic_speed = 1e-2;       ///< v_dyn [m/s] (thesis 3.9); v1 of Ambrosio
  double viscous_coefficient = 0.0;  ///< mu_v [s/m] (thesis 3.9)
};
/// The law `p.law` with its parameters; null for "none" (frictionless).
std::unique_ptr<FrictionLaw> make_friction_law(const FrictionParams& p);

/// The two branches of friction.mode stick-slip for `law` (parameters `p`), switched at the slip
/// speed v_st = p.static_speed:
///   stuck     mu(v) = law(v) (the law itself: beyond v_st only until the end of the step that
///             crossed it, when the driver switches to slipping);
///   slipping  mu(v) = law(v) where v >= v_dyn or law(v) <= law(v_dyn), else law(v_dyn)
///             (the law above v_dyn unchanged; below it capped at its value there: no drop).
/// A law without a drop (law(v_st) <= law(v_dyn)) has none: null branches (the law is used).
struct FrictionBranches {
  std::shared_ptr<const FrictionLaw> stuck, slipping;
};
FrictionBranches make_friction_branches(std::shared_ptr<const FrictionLaw> law,
                                        const FrictionParams& p);

struct ClearanceContactModel;
/// Sets the contact's friction.mode `mode` for its law m.friction (parameters `p`): smooth
/// leaves it as it is; stick-slip sets its branches and switch speed v_st; switch those and
/// the zero-velocity stick with its static limit, the law's largest mu (at v_st or v_dyn).
void set_friction_mode(ClearanceContactModel& m, FrictionMode mode, const FrictionParams& p);

/// Cubic blend of thesis eq. 3.10.
double smooth_step(double x, double x0, double f0, double x1, double f1);
/// Its derivative with respect to x (0 outside [x0, x1]).
double smooth_step_slope(double x, double x0, double f0, double x1, double f1);

/// Upper limit on the hysteresis damping term (thesis eq. 3.14), contact.damping_cap, from
/// core/damping_caps.def: none (eq. 3.6-3.8 as written), elastic (damping <= F_el, eq. 3.14).
#define RODEND_CHOICE_ENUM DampingCap
#define RODEND_CHOICE_FILE "core/damping_caps.def"
#include "core/choice.hpp"

/// Shape of the contacting surfaces (contact.geometry), from core/contact_geometries.def: it
/// alone decides the elastic force F_el(delta).
#define RODEND_CHOICE_ENUM ContactGeometry
#define RODEND_CHOICE_FILE "core/contact_geometries.def"
#include "core/choice.hpp"

/// Immutable model of one clearance contact (sphere in sphere, or cylinder in cylinder).
struct ClearanceContactModel {
  ContactGeometry geometry = ContactGeometry::sphere;
  double ball_radius = 0.0;  ///< R_b, or the pin radius of a cylinder [m]
  double clearance = 0.0;    ///< radial clearance c = R_s - R_b [m] (dR of a cylinder)
  /// Elastic coefficient K: sphere, the Hertz stiffness 4/3 E* sqrt(R*) [N/m^n]; cylinder,
  /// (pi/2) L E* [N/m] (F_el = K delta^n (2 (c + delta))^(-1/2)). Includes stiffness_scale.
  double stiffness = 0.0;
  double exponent = 1.5;                        ///< n [-]
  double hysteresis = 0.0;                      ///< chi [-]
  double min_impact_speed = 1e-3;               ///< guard on delta'^- [m/s]
  DampingCap damping_cap = DampingCap::none;    ///< eq. 3.14 cap on the damping term
  std::shared_ptr<const FrictionLaw> friction;  ///< null: frictionless
  /// friction.mode stick-slip: the law's stuck and slipping branches (null: smooth, or a law
  /// without a drop), chosen by ContactLatch::slipping, and the slip speed v_st that switches
  /// them [m/s].
  FrictionBranches branches;
  double switch_speed = 0.0;
  /// friction.mode switch: a stuck contact holds its slip velocity at zero (the scene computes
  /// the force that does, core/contact_stick.hpp, up to static_limit F_n); slipping, the
  /// slipping branch (or the law, without a drop). switch_speed is then the slip speed below
  /// which it may stick again and above which a stuck contact that exceeded the limit slips.
  bool stick = false;
  double static_limit = 0.0;  ///< mu of the static limit: the law's largest, at v_st or v_dyn [-]
  /// The law a slipping contact of the switch mode uses: the slipping branch, or the law.
  const FrictionLaw* slipping_law() const {
    return branches.slipping ? branches.slipping.get() : friction.get();
  }
  /// Worn surfaces (core/wear.hpp), fixed for a run; null: as manufactured. With them the
  /// penetration is |e| - c(n), c(n) the local clearance in the contact direction n, and the
  /// normal force acts along the gradient of that penetration (see evaluate_contact).
  std::shared_ptr<const WornSurfaces> worn;

  double socket_radius() const { return ball_radius + clearance; }
};

/// Effective modulus E*: 1/E* = (1-nu_b^2)/E_b + (1-nu_s^2)/E_s [Pa].
double effective_modulus(double E_ball, double nu_ball, double E_socket, double nu_socket);

/// Hertz stiffness of a ball inside a conformal socket (model-notes §1; thesis 3.4-3.5 fixed):
/// K = 4/3 E* sqrt(R*), R* = R_b R_s / (R_s - R_b), 1/E* = (1-nu_b^2)/E_b + (1-nu_s^2)/E_s.
double sphere_in_sphere_stiffness(double ball_radius, double socket_radius, double E_ball,
                                  double nu_ball, double E_socket, double nu_socket);

/// Coefficient K = (pi/2) L E* of the cylinder-in-cylinder law (model-notes §3) [N/m], for a
/// bearing of length L.
double cylinder_in_cylinder_coefficient(double bearing_length, double E_ball, double nu_ball,
                                        double E_socket, double nu_socket);

/// Elastic force F_el(delta) of the contact's geometry, delta > 0 [N].
double elastic_force(const ClearanceContactModel& m, double penetration);
/// Elastic energy stored at penetration delta > 0: the integral of F_el from 0 to delta [J].
/// `force` is elastic_force(m, delta) (the sphere's energy is F_el delta / (n + 1)).
double elastic_energy(const ClearanceContactModel& m, double penetration, double force);

/// Everything the contact computes at one instant. On a scalar S (double, or a dual number of
/// core/dual.hpp, core/contact_eval.hpp); ContactEval is the double one.
template <class S>
struct ContactEvalT {
  Vec3T<S> normal = Vec3T<S>::UnitX();  ///< unit vector from socket centre to ball centre
  S eccentricity = 0.0;                 ///< |p_socket - p_ball| [m]
  S penetration = 0.0;                  ///< delta [m], negative for a gap
  S penetration_rate = 0.0;             ///< delta' [m/s]
  S elastic_force = 0.0;                ///< F_el [N]
  S normal_force = 0.0;                 ///< F_n >= 0 [N]
  Vec3T<S> normal_force_on_ball = Vec3T<S>::Zero();  ///< [N]
  Vec3T<S> friction_on_ball = Vec3T<S>::Zero();      ///< [N]
  Vec3T<S> moment_on_ball = Vec3T<S>::Zero();        ///< friction moment about ball centre [N m]
  Vec3T<S> moment_on_socket = Vec3T<S>::Zero();      ///< friction moment about socket centre [N m]
  S slip_speed = 0.0;                                ///< |v_t| [m/s]
  S potential = 0.0;        ///< elastic energy, the integral of F_el over delta [J] (double only)
  S damping_power = 0.0;    ///< power dissipated by hysteresis damping [W], >= 0
  S friction_power = 0.0;   ///< power dissipated by friction [W], >= 0
  S local_clearance = 0.0;  ///< clearance in the contact direction, worn surfaces included [m]
  /// friction.mode switch, stuck: the force that holds the slip over the static limit
  /// mu F_n (core/contact_stick.hpp); above 1 the contact slides at the limit [-]. 0 otherwise.
  double stick_demand = 0.0;

  Vec3T<S> force_on_ball() const { return normal_force_on_ball + friction_on_ball; }
};
using ContactEval = ContactEvalT<double>;

/// Penetration and its rate only (cheap; used by the driver to latch onsets).
struct ContactGap {
  double penetration;
  double penetration_rate;
  /// friction.mode stick-slip or switch, in contact: the branch the slip speed calls for (1
  /// slipping: above the switch speed; 0 stuck); -1 without branches or out of contact.
  int slipping = -1;
  /// friction.mode switch: a slipping contact sticks only if the force that holds it is within
  /// the static limit too (Scene::stick_demand), and a stuck one slips above the switch speed.
  bool stick = false;
};
ContactGap contact_gap(const ClearanceContactModel& m, const BodyKinematics& ball,
                       const BodyKinematics& socket);

/// Full contact evaluation. The latch supplies delta'^-; before the driver has latched an
/// episode (trial stages past an onset), the current approach speed stands in for it.
ContactEval evaluate_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                             const BodyKinematics& socket, const ContactLatch& latch);
/// Its normal part alone, the same values: normal, eccentricity, penetration and its rate, the
/// elastic and normal forces, the potential and the damping power; the slip speed, friction and
/// the moments are left zero (what a contact snapshot reads).
ContactEval evaluate_normal_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                                    const BodyKinematics& socket, const ContactLatch& latch);

}  // namespace rodend
