// The linkage assembly's dynamics and energy (core/linkage/assembly.hpp for the equations).
#include "core/linkage/assembly.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace rodend::linkage {

int Linkage::add_body(std::unique_ptr<Body> b) {
  offsets_.push_back(n_);
  n_ += b->coordinate_count();
  bodies_.push_back(std::move(b));
  return static_cast<int>(bodies_.size()) - 1;
}
int Linkage::add_ground_point(const Eigen::Vector2d& p) {
  ground_.push_back(p);
  return static_cast<int>(ground_.size()) - 1;
}
void Linkage::add_revolute(PointRef a, PointRef b) {
  revolutes_.push_back({a, b});
}
void Linkage::add_prismatic(PointRef a, PointRef on_line, const Eigen::Vector2d& axis, double angle,
                            Guide play) {
  prismatics_.push_back({a, on_line, axis.normalized(), angle, play});
}
void Linkage::add_drive(PointRef a, PointRef rest, const Eigen::Vector2d& direction, DriveLaw law) {
  drives_.push_back({a, rest, direction.normalized(), std::move(law)});
}
void Linkage::add_rotary_drive(PointRef a, double angle0, DriveLaw law) {
  Drive d{a, a, Eigen::Vector2d::Zero(), std::move(law)};
  d.rotary = true;
  d.angle0 = angle0;
  drives_.push_back(std::move(d));
}
void Linkage::add_motor(PointRef a, double angle0, double speed, double slope, double flywheel) {
  motors_.push_back({a, angle0, speed, slope, flywheel});
}
int Linkage::add_clearance_joint(ClearanceJoint j) {
  clearance_.push_back(std::move(j));
  return static_cast<int>(clearance_.size()) - 1;
}

void Linkage::finish() {
  for (Drive& d : drives_)  // a guided body's point: the guide holds it across the direction
    d.guided = !d.rotary && std::any_of(prismatics_.begin(), prismatics_.end(),
                                        [&](const Prismatic& g) { return g.a.body == d.a.body; });
  auto ideal = std::make_shared<Linkage>(*this);
  ideal->ideal_.reset();
  for (const ClearanceJoint& j : clearance_) ideal->add_revolute(j.journal, j.bearing);
  ideal->clearance_.clear();
  for (Prismatic& g : ideal->prismatics_) g.play = Guide{};
  for (const Motor& m : motors_)  // the ideal linkage's motor holds its no-load speed
    ideal->add_rotary_drive(m.a, m.angle0, [w = m.speed](double t) {
      return DriveSample{w * t, w, 0.0};
    });
  ideal->motors_.clear();
  ideal->rigid_ = true;  // and every flexible body rigid: its modal amplitudes held at zero
  ideal_ = std::move(ideal);
}

Eigen::MatrixXd Linkage::mass_matrix(const Eigen::VectorXd& q) const {
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n_, n_);
  for (int b = 0; b < body_count(); ++b) {
    const int o = body_offset(b), k = body(b).coordinate_count();
    M.block(o, o, k, k) = body(b).mass_matrix(q.segment(o, k));
  }
  for (const Motor& m : motors_) {  // the flywheel turns with the motor's section
    const GlobalPoint a = point(m.a, q, Eigen::VectorXd::Zero(n_));
    M += m.flywheel * a.angle_jacobian.transpose() * a.angle_jacobian;
  }
  return M;
}

std::pair<BodyKinematics, BodyKinematics> Linkage::joint_kinematics(
    int i, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  const ClearanceJoint& j = clearance_[static_cast<std::size_t>(i)];
  auto kin = [&](PointRef r) {
    const GlobalPoint g = point(r, q, qd);
    BodyKinematics k = BodyKinematics::fixed(Vec3(g.position.x(), g.position.y(), 0.0));
    k.v_W = Vec3(g.velocity.x(), g.velocity.y(), 0.0);
    k.w_W = k.w_B = Vec3(0.0, 0.0, g.angular_velocity);
    return k;
  };
  return {kin(j.journal), kin(j.bearing)};
}

Eigen::VectorXd Linkage::applied_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                        const std::vector<ContactLatch>& latches,
                                        LinkageDynamics& out) const {
  Eigen::VectorXd Q = Eigen::VectorXd::Zero(n_);
  for (int b = 0; b < body_count(); ++b) {
    const int o = body_offset(b), k = body(b).coordinate_count();
    Q.segment(o, k) = body(b).internal_forces(q.segment(o, k), qd.segment(o, k), gravity_);
    out.dissipation += body(b).dissipated_power(q.segment(o, k), qd.segment(o, k));
  }
  out.contacts.resize(clearance_.size());
  for (std::size_t i = 0; i < clearance_.size(); ++i) {
    const auto [journal, bearing] = joint_kinematics(static_cast<int>(i), q, qd);
    const ContactLatch latch = i < latches.size() ? latches[i] : ContactLatch{};
    const ContactEval c = evaluate_contact(clearance_[i].model, journal, bearing, latch);
    const Eigen::Vector2d F = c.force_on_ball().head<2>();
    const GlobalPoint a = point(clearance_[i].journal, q, qd);
    const GlobalPoint b = point(clearance_[i].bearing, q, qd);
    Q += a.jacobian.transpose() * F + a.angle_jacobian.transpose() * c.moment_on_ball.z();
    Q -= b.jacobian.transpose() * F;
    Q += b.angle_jacobian.transpose() * c.moment_on_socket.z();
    out.dissipation += c.damping_power + c.friction_power;
    out.contacts[i] = c;
  }
  for (const Prismatic& g : prismatics_)
    if (g.play.on()) add_guide_forces(g, q, qd, Q, out.dissipation);
  for (const Motor& m : motors_) {
    const GlobalPoint a = point(m.a, q, qd);
    // the motor curve's torque, and the flywheel's velocity product -I (jd q') on the angle
    const double torque = m.slope * (m.speed - a.angular_velocity);
    Q += a.angle_jacobian.transpose() * (torque - m.flywheel * a.angle_jacobian_dot_qdot);
    out.motor_torques.push_back(torque);
    out.motor_power += torque * a.angular_velocity;
  }
  return Q;
}

LinkageDynamics Linkage::dynamics(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                  const std::vector<ContactLatch>& latches) const {
  LinkageDynamics out;
  const Eigen::VectorXd Q = applied_forces(q, qd, latches, out);
  const ConstraintRows c = constraints(t, q, qd);
  const int m = constraint_count();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n_ + m, n_ + m);
  A.topLeftCorner(n_, n_) = mass_matrix(q);
  A.topRightCorner(n_, m) = c.jacobian.transpose();
  A.bottomLeftCorner(m, n_) = c.jacobian;
  Eigen::VectorXd rhs(n_ + m);
  rhs.head(n_) = Q;
  const double w = baumgarte_;
  rhs.tail(m) = -c.b2 - 2.0 * w * (c.jacobian * qd + c.b1) - w * w * c.value;
  const Eigen::VectorXd x = A.partialPivLu().solve(rhs);
  out.qdd = x.head(n_);
  out.multipliers = x.tail(m);
  // the constraint forces on the bodies are -Cq^T lam; their power
  out.constraint_power = -out.multipliers.dot(c.jacobian * qd);
  for (std::size_t i = 0; i < drives_.size(); ++i) {
    const Drive& d = drives_[i];
    const int r = drive_row(static_cast<int>(i));
    // a rotary or guided drive's row is its direction's (or angle's) own: its force is -lam;
    // the two rows of a free point: the force -lam projected on the direction
    out.drive_forces.push_back(d.rows() == 1 ? -out.multipliers[r]
                                             : -d.direction.dot(out.multipliers.segment<2>(r)));
  }
  return out;
}

double Linkage::kinetic_energy(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  double e = 0.0;
  for (int b = 0; b < body_count(); ++b) {
    const int o = body_offset(b), k = body(b).coordinate_count();
    e += body(b).kinetic_energy(q.segment(o, k), qd.segment(o, k));
  }
  for (const Motor& m : motors_) {
    const double w = point(m.a, q, qd).angular_velocity;
    e += 0.5 * m.flywheel * w * w;
  }
  return e;
}

double Linkage::potential_energy(const Eigen::VectorXd& q) const {
  double e = 0.0;
  for (int b = 0; b < body_count(); ++b) {
    const int o = body_offset(b), k = body(b).coordinate_count();
    e += body(b).potential_energy(q.segment(o, k), gravity_);
  }
  for (const Prismatic& g : prismatics_) e += guide_potential(g, q);
  return e;
}

void Linkage::add_guide_forces(const Prismatic& j, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& qd, Eigen::VectorXd& Q,
                               double& dissipation) const {
  // the slider-crank's guide law: y across the line (along n), v along it
  const GlobalPoint a = point(j.a, q, qd), o = point(j.on_line, q, qd);
  const Eigen::Vector2d n(-j.axis.y(), j.axis.x());
  const Guide::Force f =
      j.play.force(n.dot(a.position - o.position), n.dot(a.velocity), j.axis.dot(a.velocity));
  Q += a.jacobian.transpose() * (f.fy * n + f.fx * j.axis);
  dissipation += f.dissipation;
}

double Linkage::guide_potential(const Prismatic& j, const Eigen::VectorXd& q) const {
  if (!j.play.on()) return 0.0;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n_);
  const GlobalPoint a = point(j.a, q, zero), o = point(j.on_line, q, zero);
  const Eigen::Vector2d n(-j.axis.y(), j.axis.x());
  return j.play.force(n.dot(a.position - o.position), 0.0, 0.0).potential;
}

}  // namespace rodend::linkage
