#include "core/scenes/parts.hpp"

#include <cmath>
#include <cstdio>

namespace rodend {

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

double read_positive(const ParameterSet& p, const std::string& path, bool allow_zero) {
  const double v = p.number(path);
  if (allow_zero ? !(v >= 0.0) : !(v > 0.0))
    throw InputError(path, std::string("expected a value ") + (allow_zero ? ">= 0" : "> 0") + " [" +
                               p.unit(path) + "], got " + format_number(v));
  return v;
}

RigidBodyParams read_body(const ParameterSet& p, const std::string& prefix) {
  RigidBodyParams b;
  b.mass = read_positive(p, prefix + ".mass");
  b.inertia = p.vec3(prefix + ".inertia");
  for (int i = 0; i < 3; ++i)
    if (!(b.inertia[i] > 0.0))
      throw InputError(prefix + ".inertia", "expected three principal moments > 0 [kg*m^2]");
  return b;
}

namespace {

/// The geometry's Hertz coefficient from the two materials (contact.hpp); sets m.geometry.
double read_hertz_coefficient(const ParameterSet& p, const std::string& prefix,
                              ClearanceContactModel& m) {
  const double Eb = read_positive(p, prefix + ".ball_youngs_modulus");
  const double Es = read_positive(p, prefix + ".socket_youngs_modulus");
  const double nub = p.number(prefix + ".ball_poisson_ratio");
  const double nus = p.number(prefix + ".socket_poisson_ratio");
  if (!(nub > -1.0 && nub < 0.5))
    throw InputError(prefix + ".ball_poisson_ratio", "expected -1 < nu < 0.5");
  if (!(nus > -1.0 && nus < 0.5))
    throw InputError(prefix + ".socket_poisson_ratio", "expected -1 < nu < 0.5");
  // the elastic force is the geometry's (contact.hpp); the laws below supply only chi(c_r)
  m.geometry = read_choice<ContactGeometry>(p, prefix + ".geometry");
  switch (m.geometry) {
    case ContactGeometry::sphere:
      return sphere_in_sphere_stiffness(m.ball_radius, m.socket_radius(), Eb, nub, Es, nus);
    case ContactGeometry::cylinder:
      return cylinder_in_cylinder_coefficient(read_positive(p, prefix + ".bearing_length"), Eb, nub,
                                              Es, nus);
  }
  return 0.0;
}

/// The friction law of a clearance contact, keys under `fprefix`.
void read_friction(const ParameterSet& p, const std::string& fprefix, ClearanceContactModel& m,
                   bool holds_stick) {
  FrictionParams f;
  const std::string law = p.text(fprefix + ".law");
  const auto kind = choice_from_name<FrictionLawKind>(law);
  if (!kind) throw InputError(fprefix + ".law", "unknown friction law '" + law + "'");
  f.law = *kind;
  f.static_coefficient = read_positive(p, fprefix + ".static_coefficient", true);
  f.dynamic_coefficient = read_positive(p, fprefix + ".dynamic_coefficient", true);
  f.static_speed = read_positive(p, fprefix + ".static_speed");
  f.dynamic_speed = read_positive(p, fprefix + ".dynamic_speed");
  f.viscous_coefficient = read_positive(p, fprefix + ".viscous_coefficient", true);
  if (needs_ordered_speeds(f.law) && !(f.dynamic_speed > f.static_speed))
    throw InputError(fprefix + ".dynamic_speed", "expected dynamic_speed > static_speed");
  m.friction = make_friction_law(f);
  const FrictionMode mode = read_choice<FrictionMode>(p, fprefix + ".mode");
  if (mode == FrictionMode::switch_model && !holds_stick)
    throw InputError(fprefix + ".mode",
                     "the mode 'switch' needs a scene that computes a stuck contact's force "
                     "(the rod-end scenes); expected 'smooth' or 'stick-slip'");
  set_friction_mode(m, mode, f);
}

}  // namespace

ClearanceContactModel read_clearance_contact(const ParameterSet& p, const std::string& prefix,
                                             const std::string& fprefix,
                                             const std::string& clearance_path, bool holds_stick) {
  ClearanceContactModel m;
  m.ball_radius = read_positive(p, prefix + ".ball_radius");
  const std::string cpath = clearance_path.empty() ? prefix + ".clearance" : clearance_path;
  const double c = p.number(cpath);
  if (!(c > 0.0))
    throw InputError(cpath,
                     "expected a clearance > 0 [m] (the socket radius must exceed the ball "
                     "radius), got " +
                         format_number(c));
  m.clearance = c;
  const double coefficient = read_hertz_coefficient(p, prefix, m);
  if (!std::isfinite(coefficient))  // Rs - Rb rounds to 0: the conformal radius is infinite
    throw InputError(prefix + ".clearance",
                     "is too small for the radii: the socket's radius rounds to the ball's, so the "
                     "Hertz coefficient is not a finite number; expected a larger clearance");
  const double scale = p.number(prefix + ".stiffness_scale");
  if (!(scale > 0.0)) throw InputError(prefix + ".stiffness_scale", "expected a value > 0");
  m.stiffness = scale * coefficient;
  if (!std::isfinite(m.stiffness))
    throw InputError(prefix + ".stiffness_scale",
                     "makes the contact stiffness overflow (the scale times the Hertz "
                     "coefficient is not a finite number); expected a scale that keeps it finite");
  m.exponent = 1.5;  // both geometries (thesis 3.3; model-notes §3)
  const std::string law_name = p.text(prefix + ".law");
  const NormalLaw* law = find_normal_law(law_name);
  if (!law) throw InputError(prefix + ".law", "unknown normal-contact law '" + law_name + "'");
  const double cr = p.number(prefix + ".restitution");
  if (!(cr >= 0.0 && cr <= 1.0))
    throw InputError(prefix + ".restitution", "expected a restitution coefficient in [0, 1]");
  if (cr == 0.0 && !law->defined_at_zero_restitution())
    throw InputError(prefix + ".restitution",
                     "law '" + law_name + "' divides by c_r and is undefined at c_r = 0");
  m.hysteresis = law->hysteresis_factor(cr);
  m.min_impact_speed = read_positive(p, prefix + ".min_impact_speed");
  const std::string cap = p.text(prefix + ".damping_cap");
  const auto damping_cap = choice_from_name<DampingCap>(cap);
  if (!damping_cap) throw InputError(prefix + ".damping_cap", "unknown damping cap '" + cap + "'");
  m.damping_cap = *damping_cap;

  read_friction(p, fprefix, m, holds_stick);
  return m;
}

Spring3DParams read_spring(const ParameterSet& p, const std::string& prefix) {
  Spring3DParams s;
  s.stiffness = read_positive(p, prefix + ".stiffness", true);
  s.damping = read_positive(p, prefix + ".damping", true);
  s.rotational_stiffness = read_positive(p, prefix + ".rotational_stiffness", true);
  s.rotational_damping = read_positive(p, prefix + ".rotational_damping", true);
  return s;
}

}  // namespace rodend

namespace rodend {

void write_energy_signals(SignalFrame& frame, const EnergyTerms& e, double initial_mechanical) {
  frame.set(SignalId::mechanical_energy, e.mechanical);
  frame.set(SignalId::input_work, e.input_work);
  frame.set(SignalId::dissipated_energy, e.dissipated);
  frame.set(SignalId::energy_residual,
            (e.mechanical - initial_mechanical) - e.input_work + e.dissipated);
}

void body_state_scale(double* s, double length, double speed, double angular_rate) {
  for (int i = 0; i < 3; ++i) {
    s[BodyStateLayout::p + i] = length;
    s[BodyStateLayout::v + i] = speed;
    s[BodyStateLayout::w + i] = angular_rate;
  }
  for (int i = 0; i < 4; ++i) s[BodyStateLayout::q + i] = 1.0;
}

double quaternion_norm_error(const double* x, int o) {
  return std::abs(
      std::sqrt(x[o] * x[o] + x[o + 1] * x[o + 1] + x[o + 2] * x[o + 2] + x[o + 3] * x[o + 3]) -
      1.0);
}

}  // namespace rodend

namespace rodend {

void write_contact_signals(SignalFrame& f, const ContactEval& c, const BodyKinematics& ball,
                           const BodyKinematics& socket, const ContactLatch& latch) {
  const Vec3 rel = ball.p_W - socket.p_W;
  f.set(SignalId::eccentricity_vector, Vec3(-rel));
  f.set(SignalId::eccentricity, c.eccentricity);
  f.set(SignalId::relative_position, rel);
  f.set(SignalId::penetration, c.penetration);
  f.set(SignalId::penetration_rate, c.penetration_rate);
  f.set(SignalId::impact_speed, latch.in_contact ? latch.impact_speed : 0.0);
  f.set(SignalId::contact_force_vector, c.normal_force_on_ball);
  f.set(SignalId::contact_force, c.normal_force);
  f.set(SignalId::friction_force_vector, c.friction_on_ball);
  f.set(SignalId::friction_force, c.friction_on_ball.norm());
  f.set(SignalId::slip_speed, c.normal_force > 0.0 ? c.slip_speed : 0.0);
  f.set(SignalId::wear_indicator, c.normal_force * c.slip_speed);
  f.set(SignalId::contact_angle, std::atan2(rel.y(), rel.x()));
}

}  // namespace rodend
