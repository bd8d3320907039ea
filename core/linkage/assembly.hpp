#pragma once
// The planar linkage assembly (docs/planar-linkage.md): bodies in absolute coordinates, ideal
// joints and drives as constraints with Lagrange multipliers, revolute joints with radial
// clearance as force elements (the clearance contact of core/contact.hpp), gravity.
//
// It talks to its bodies only through Body (core/linkage/body.hpp): a rigid or a flexible body
// plugs in unchanged. With q the coordinates of all bodies stacked, C(q, t) = 0 the constraints,
// Cq their Jacobian and Q the bodies' internal forces plus the clearance joints' forces:
//   [ M   Cq^T ] [ q'' ]   [ Q                                        ]
//   [ Cq  0    ] [ lam ] = [ -b2 - 2 w (Cq q' + b1) - w^2 C           ]
// where C' = Cq q' + b1 and C'' = Cq q'' + b2 (b1: the drives' explicit time dependence, b2 the
// velocity products and the drives' accelerations). The last two terms are Baumgarte's
// stabilisation with one rate w [1/s], critically damped: the drift obeys C'' + 2 w C' + w^2 C
// = 0 and decays instead of growing; nothing projects the state, so the state changes only
// continuously (the scene reports the drift as the constraint_drift signal).
#include <functional>
#include <memory>
#include <vector>

#include "core/contact.hpp"
#include "core/linkage/body.hpp"
#include "core/scenes/planar_slider_crank_options.hpp"

namespace rodend::linkage {

/// A material point: `point` of body `body`, or with body -1 the ground point `point`.
struct PointRef {
  int body = -1;
  int point = 0;
};

/// A prescribed displacement d(t) and its first two time derivatives [m, m/s, m/s^2].
struct DriveSample {
  double value = 0.0, rate = 0.0, acceleration = 0.0;
};
using DriveLaw = std::function<DriveSample(double t)>;

/// A point of the linkage with its Jacobian over all coordinates (2 x n; the angle row 1 x n).
struct GlobalPoint {
  Eigen::Vector2d position = Eigen::Vector2d::Zero(), velocity = Eigen::Vector2d::Zero();
  Eigen::MatrixXd jacobian;
  Eigen::Vector2d jacobian_dot_qdot = Eigen::Vector2d::Zero();
  double angle = 0.0, angular_velocity = 0.0, angle_jacobian_dot_qdot = 0.0;
  Eigen::RowVectorXd angle_jacobian;
};

/// The constraints at (t, q, q'): C' = Cq q' + b1, C'' = Cq q'' + b2.
struct ConstraintRows {
  Eigen::VectorXd value, b1, b2;
  Eigen::MatrixXd jacobian;
  std::vector<bool> is_angle;  ///< rows in [rad] (a guide's angle); the others in [m]
};

/// A revolute joint with radial clearance: journal on one body, bearing on another (or ground).
struct ClearanceJoint {
  PointRef journal, bearing;
  ClearanceContactModel model;
};

/// Accelerations and forces at one instant.
struct LinkageDynamics {
  Eigen::VectorXd qdd, multipliers;
  std::vector<ContactEval> contacts;  ///< per clearance joint, in order of addition
  /// per drive, in order of addition: the force the drive applies along its direction [N], or
  /// the torque a rotary drive applies to its body [N m] (counter-clockwise positive)
  std::vector<double> drive_forces;
  std::vector<double> motor_torques;  ///< per motor: its torque on its body [N m]
  double motor_power = 0.0;           ///< the motors' power on the bodies [W]
  double dissipation = 0.0;           ///< contact damping and friction power [W]
  double constraint_power = 0.0;      ///< power of the constraint forces on the bodies [W]
};

class Linkage {
 public:
  int add_body(std::unique_ptr<Body> body);
  int add_ground_point(const Eigen::Vector2d& position);
  /// An ideal revolute joint: the two points coincide.
  void add_revolute(PointRef a, PointRef b);
  /// A prismatic guide fixed to the ground: point `a` stays on the line through ground point
  /// `on_line` along `axis`, and a's body keeps its initial angle `angle` [rad]. With `play`
  /// on (Guide::clearance), the point moves across the line between two walls at -+ the
  /// play, the slider-crank's guide law (core/scenes/planar_slider_crank_options.hpp): only
  /// the angle is a constraint, the walls and the friction along the guide are forces.
  void add_prismatic(PointRef a, PointRef on_line, const Eigen::Vector2d& axis, double angle,
                     Guide play = {});
  /// A prescribed actuator displacement: point `a` at ground point `rest` + d(t) `direction`
  /// (only along `direction` when a's body is on a prismatic guide: the guide holds it across).
  void add_drive(PointRef a, PointRef rest, const Eigen::Vector2d& direction, DriveLaw law);
  /// A prescribed angle: the angle of point `a`'s section is `angle0` + d(t) [rad] (a crank
  /// at constant speed, d = omega t, or any command).
  void add_rotary_drive(PointRef a, double angle0, DriveLaw law);
  /// A motor on the section at `a`: torque slope (speed - its angular velocity) (a linear
  /// motor curve about the no-load `speed` [rad/s], `slope` [N m s/rad]) through a flywheel of
  /// inertia `flywheel` [kg m^2] turning with it. The ideal linkage turns it at `speed` from
  /// `angle0` instead (a rotary drive).
  void add_motor(PointRef a, double angle0, double speed, double slope, double flywheel);
  int add_clearance_joint(ClearanceJoint joint);
  void set_gravity(const Eigen::Vector2d& g) { gravity_ = g; }
  void set_baumgarte_rate(double w) { baumgarte_ = w; }

  int coordinate_count() const { return n_; }
  int constraint_count() const;
  int body_count() const { return static_cast<int>(bodies_.size()); }
  int body_offset(int b) const { return offsets_[static_cast<std::size_t>(b)]; }
  const Body& body(int b) const { return *bodies_[static_cast<std::size_t>(b)]; }
  const std::vector<ClearanceJoint>& clearance_joints() const { return clearance_; }
  /// The same linkage with every clearance joint an ideal revolute joint, every guide with play
  /// ideal and every flexible body rigid (its coordinates beyond the frame's three held at 0).
  std::shared_ptr<const Linkage> ideal() const { return ideal_; }
  /// Builds ideal() (call once, after the last add_*).
  void finish();

  GlobalPoint point(PointRef r, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  ConstraintRows constraints(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  LinkageDynamics dynamics(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                           const std::vector<ContactLatch>& latches) const;
  /// Journal and bearing of clearance joint i as the contact's body kinematics.
  std::pair<BodyKinematics, BodyKinematics> joint_kinematics(int i, const Eigen::VectorXd& q,
                                                             const Eigen::VectorXd& qd) const;
  double kinetic_energy(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const;
  /// The bodies' gravity and elastic energy and the guides' walls' [J].
  double potential_energy(const Eigen::VectorXd& q) const;

  /// Newton on C(q, t) = 0 from q (least-norm steps); returns the final largest |C| [m or rad].
  double assemble(double t, Eigen::VectorXd& q, int iterations = 50) const;
  /// The least-norm q' with C' = 0 at (t, q).
  Eigen::VectorXd consistent_velocity(double t, const Eigen::VectorXd& q) const;

 private:
  struct Revolute {
    PointRef a, b;
  };
  struct Prismatic {
    PointRef a, on_line;
    Eigen::Vector2d axis;
    double angle;
    Guide play;  ///< model ideal: two rows; clearance: the angle row and the walls' forces
    int rows() const { return play.on() ? 1 : 2; }
  };
  struct Drive {
    PointRef a, rest;
    Eigen::Vector2d direction;
    DriveLaw law;
    bool rotary = false;  ///< the angle of a's section, rest and direction unused
    double angle0 = 0.0;  ///< the rotary drive's angle at d = 0 [rad]
    bool guided = false;  ///< a's body is on a prismatic guide: one row, along the direction
    int rows() const { return rotary || guided ? 1 : 2; }
  };
  struct Motor {
    PointRef a;
    double angle0, speed, slope, flywheel;
  };
  /// The first row of drive i (the drives' rows follow the joints').
  int drive_row(int i) const;
  /// A guide with play's walls and friction on its point: added to Q, and their dissipated
  /// power (the walls' damping, the friction) to `dissipation`; guide_potential: the walls'
  /// elastic energy.
  void add_guide_forces(const Prismatic& j, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                        Eigen::VectorXd& Q, double& dissipation) const;
  double guide_potential(const Prismatic& j, const Eigen::VectorXd& q) const;
  void add_revolute_rows(const Revolute& j, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         ConstraintRows& c, int row) const;
  void add_prismatic_rows(const Prismatic& j, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                          ConstraintRows& c, int row) const;
  /// The rows holding a body's coordinates beyond its frame's (modal amplitudes) at zero.
  void add_rigid_rows(const Eigen::VectorXd& q, ConstraintRows& c, int row) const;
  int rigid_row_count() const;
  void add_drive_rows(double t, const Drive& j, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                      ConstraintRows& c, int row) const;
  /// Q: the bodies' internal forces and the clearance joints' forces (filled into `out`).
  Eigen::VectorXd applied_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                 const std::vector<ContactLatch>& latches,
                                 LinkageDynamics& out) const;
  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) const;

  std::vector<std::shared_ptr<const Body>> bodies_;
  std::vector<int> offsets_;
  std::vector<Eigen::Vector2d> ground_;
  std::vector<Revolute> revolutes_;
  std::vector<Prismatic> prismatics_;
  std::vector<Drive> drives_;
  std::vector<Motor> motors_;
  std::vector<ClearanceJoint> clearance_;
  Eigen::Vector2d gravity_ = Eigen::Vector2d::Zero();
  double baumgarte_ = 0.0;
  int n_ = 0;
  bool rigid_ = false;  ///< the ideal linkage: flexible bodies held rigid
  std::shared_ptr<const Linkage> ideal_;
};

}  // namespace rodend::linkage
