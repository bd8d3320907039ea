// Scene planar-slider-crank, the model forms of issue 36 item 4: each an option of the scene, a
// parameter block read once into an immutable model, its choice an enum (the names only in its
// menu, core/scenes/rod_models.def, guide_models.def, drive_models.def).
//   rod_flexibility  the connecting rod's first bending mode in a floating frame (rigid: none);
//   guide            the slider's guide with clearance and friction (ideal: a rigid,
//                    frictionless guide);
//   drive            the crank driven by a motor curve through a flywheel (prescribed_speed:
//                    the motor holds the speed exactly).
// The defaults are the options off: today's model. docs/planar-slider-crank.md, "Model forms".
#pragma once

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>

#include "core/choice.hpp"
#include "core/contact.hpp"
#include "core/errors.hpp"
#include "core/params.hpp"
#include "core/scenes/parts.hpp"

namespace rodend {

/// The menus of the model forms (core/choice.hpp), read by read_choice (parts.hpp).
#define RODEND_CHOICE_ENUM RodModel
#define RODEND_CHOICE_FILE "core/scenes/rod_models.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM GuideModel
#define RODEND_CHOICE_FILE "core/scenes/guide_models.def"
#include "core/choice.hpp"
#define RODEND_CHOICE_ENUM DriveModel
#define RODEND_CHOICE_FILE "core/scenes/drive_models.def"
#include "core/choice.hpp"
/// A revolute joint of the mechanism: ideal, or with clearance (`<joint>.model`).
#define RODEND_CHOICE_ENUM JointModel
#define RODEND_CHOICE_FILE "core/scenes/joint_models.def"
#include "core/choice.hpp"

/// The connecting rod's first bending mode, pinned-pinned in the chord frame (the frame through
/// the two bore centres, so the joints see no deflection): w(s, t) = eta(t) sin(pi s / L), of a
/// uniform Euler-Bernoulli beam of the rod's mass and length. The mode's kinetic energy is the
/// beam's with the deflection minus the beam's without it, at 5 Gauss-Legendre points along the
/// rod (each point a mass m w_k / 2 moving with the rod plus eta psi_k normal to its chord), so
/// the rigid rod with the table's mass and inertia is kept exactly and eta = 0 is the rigid rod.
struct RodMode {
  using Model = RodModel;
  static constexpr int kPoints = 5;
  Model model = Model::rigid;
  double stiffness = 0.0;  ///< modal stiffness EI (pi/L)^4 L/2 [N/m]
  double damping = 0.0;    ///< modal damping 2 zeta sqrt(k m/2) [N s/m]
  double frequency = 0.0;  ///< first bending frequency (pi/L)^2 sqrt(EI L/m) [rad/s]
  std::array<double, kPoints> s{}, psi{}, mass{};  ///< point: distance from B, sin(pi s/L), m w/2
  bool on() const { return model == Model::first_mode; }

  static RodMode read(const ParameterSet& p, double L, double m, double inertia, double com) {
    RodMode r;
    r.model = read_choice<RodModel>(p, "rod_flexibility.model");
    if (!r.on()) return r;
    const double E = read_positive(p, "rod_flexibility.youngs_modulus");
    const double I = read_positive(p, "rod_flexibility.section_second_moment");
    const double zeta = read_positive(p, "rod_flexibility.damping_ratio", true);
    // the split into a uniform beam and the rest must leave the rest a mass-free rotary inertia
    if (std::abs(com - 0.5 * L) > 1e-9 * L)
      throw InputError("rod.center_of_mass",
                       "expected the rod's mass centre at mid-length (" + format_number(0.5 * L) +
                           " m) with rod_flexibility.model \"first_mode\" (a uniform beam's mode)");
    if (inertia < m * L * L / 12.0)
      throw InputError("rod.inertia", "expected at least a uniform bar's m L^2/12 = " +
                                          format_number(m * L * L / 12.0) +
                                          " kg m^2 with rod_flexibility.model \"first_mode\"");
    const double k = std::numbers::pi / L;
    r.stiffness = E * I * k * k * k * k * L / 2.0;
    r.damping = 2.0 * zeta * std::sqrt(r.stiffness * m / 2.0);
    r.frequency = k * k * std::sqrt(E * I * L / m);
    static constexpr std::array<double, kPoints> xi{-0.9061798459386640, -0.5384693101056831, 0.0,
                                                    0.5384693101056831, 0.9061798459386640};
    static constexpr std::array<double, kPoints> w{0.2369268850561891, 0.4786286704993665,
                                                   0.5688888888888889, 0.4786286704993665,
                                                   0.2369268850561891};
    for (int i = 0; i < kPoints; ++i) {
      const auto u = static_cast<std::size_t>(i);
      r.s[u] = 0.5 * L * (1.0 + xi[u]);
      r.psi[u] = std::sin(k * r.s[u]);
      r.mass[u] = 0.5 * m * w[u];
    }
    return r;
  }
};

/// The slider's guide. ideal: rigid and frictionless (the slider's y is 0). clearance: the
/// slider moves across the guide between two walls at y = -+clearance (a coordinate; it does not
/// tilt), each wall a linear spring-damper acting only in penetration, and Coulomb friction
/// mu F_n along the guide, regularised below friction_speed (Ambrosio's c_d ramp from
/// friction_speed/10 to friction_speed).
struct Guide {
  using Model = GuideModel;
  Model model = Model::ideal;
  double clearance = 0.0;  ///< half the play across the guide [m]
  double stiffness = 0.0;  ///< wall stiffness [N/m]
  double damping = 0.0;    ///< wall damping 2 zeta sqrt(k m_slider) [N s/m]
  double friction = 0.0;   ///< Coulomb coefficient [-]
  double speed = 1e-3;     ///< friction regularisation speed [m/s]
  bool on() const { return model == Model::clearance; }

  static Guide read(const ParameterSet& p, double slider_mass) {
    Guide g;
    g.model = read_choice<GuideModel>(p, "guide.model");
    if (!g.on()) return g;
    g.clearance = read_positive(p, "guide.clearance");
    g.stiffness = read_positive(p, "guide.stiffness");
    g.damping =
        2.0 * read_positive(p, "guide.damping_ratio", true) * std::sqrt(g.stiffness * slider_mass);
    g.friction = read_positive(p, "guide.friction_coefficient", true);
    g.speed = read_positive(p, "guide.friction_speed");
    return g;
  }

  /// The guide's force on the slider at y, y' (across) and v (along): Fy, Fx, the wall's
  /// elastic energy and the power dissipated by its damping and the friction.
  struct Force {
    double fy = 0.0, fx = 0.0, normal = 0.0, potential = 0.0, dissipation = 0.0;
  };
  Force force(double y, double y_rate, double v) const {
    Force f;
    const double delta = std::abs(y) - clearance;
    if (!on() || delta <= 0.0) return f;
    const double n = y > 0.0 ? 1.0 : -1.0;  // the wall's outward normal
    const double rate = n * y_rate;         // penetration rate
    f.normal = std::max(0.0, stiffness * delta + damping * rate);
    f.fy = -n * f.normal;
    f.potential = 0.5 * stiffness * delta * delta;
    const double ramp = smooth_step(std::abs(v), 0.1 * speed, 0.0, speed, 1.0);
    f.fx = v == 0.0 ? 0.0 : -std::copysign(friction * f.normal * ramp, v);
    f.dissipation = (f.normal - stiffness * delta) * rate - f.fx * v;
    return f;
  }
};

/// The crank's drive. prescribed_speed: theta = theta_0 + omega t, the torque from inverse
/// dynamics. motor: theta is a coordinate, driven by a linear motor curve (a proportional speed
/// controller) tau = slope (omega - theta') about the no-load speed omega = drive.crank_speed,
/// through the flywheel's inertia (motor rotor, gear and flywheel, referred to the crank shaft).
struct Drive {
  using Model = DriveModel;
  Model model = Model::prescribed_speed;
  double flywheel = 0.0;  ///< [kg m^2] about the crank axis
  double slope = 0.0;     ///< [N m s/rad]
  bool on() const { return model == Model::motor; }

  static Drive read(const ParameterSet& p) {
    Drive d;
    d.model = read_choice<DriveModel>(p, "drive.model");
    if (!d.on()) return d;
    d.flywheel = read_positive(p, "drive.flywheel_inertia");
    d.slope = read_positive(p, "drive.motor_slope");
    return d;
  }
  double torque(double omega, double rate) const { return slope * (omega - rate); }
};

}  // namespace rodend
