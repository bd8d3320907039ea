// The linkage's ideal joints and drives as constraint rows (core/linkage/assembly.hpp), and the
// position and velocity solves on them (assembly of the initial state, the ideal linkage).
//   revolute a-b:   C = r_a - r_b,                 C'' = Cq q'' + (Jd q')_a - (Jd q')_b
//   prismatic a:    C = n . (r_a - r_0), phi_a - phi_0  (n normal to the guide's axis; with
//                   play only the angle row, the walls are forces)
//   drive a:        C = r_a - r_rest - d(t) u,     b1 = -d' u,  C'' = Cq q'' + (Jd q')_a - d'' u
//                   (a guided body's point: the row along u only, u . (r_a - r_rest) - d(t))
//   rotary drive a: C = phi_a - phi_0 - d(t),      b1 = -d',    C'' = Cq q'' + (jd q')_a - d''

#include <algorithm>
#include <cmath>

#include "core/linkage/assembly.hpp"

namespace rodend::linkage {

int Linkage::constraint_count() const {
  int m = 2 * static_cast<int>(revolutes_.size()) + rigid_row_count();
  for (const Prismatic& j : prismatics_) m += j.rows();
  for (const Drive& j : drives_) m += j.rows();
  return m;
}

int Linkage::drive_row(int i) const {
  int row = 2 * static_cast<int>(revolutes_.size());
  for (const Prismatic& j : prismatics_) row += j.rows();
  for (int k = 0; k < i; ++k) row += drives_[static_cast<std::size_t>(k)].rows();
  return row;
}

int Linkage::rigid_row_count() const {
  int m = 0;
  for (int b = 0; rigid_ && b < body_count(); ++b) m += body(b).coordinate_count() - 3;
  return m;
}

void Linkage::add_rigid_rows(const Eigen::VectorXd& q, ConstraintRows& c, int row) const {
  for (int b = 0; rigid_ && b < body_count(); ++b)
    for (int k = body_offset(b) + 3; k < body_offset(b) + body(b).coordinate_count(); ++k, ++row) {
      c.value[row] = q[k];
      c.jacobian(row, k) = 1.0;
      c.b1[row] = c.b2[row] = 0.0;
    }
}

GlobalPoint Linkage::point(PointRef r, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
  GlobalPoint g;
  g.jacobian = Eigen::MatrixXd::Zero(2, n_);
  g.angle_jacobian = Eigen::RowVectorXd::Zero(n_);
  if (r.body < 0) {
    g.position = ground_[static_cast<std::size_t>(r.point)];
    return g;
  }
  const Body& b = body(r.body);
  const int o = body_offset(r.body), k = b.coordinate_count();
  const PointKinematics p = b.point(r.point, q.segment(o, k), qd.segment(o, k));
  g.position = p.position;
  g.velocity = p.velocity;
  g.jacobian.middleCols(o, k) = p.jacobian;
  g.jacobian_dot_qdot = p.jacobian_dot_qdot;
  g.angle = p.angle;
  g.angular_velocity = p.angular_velocity;
  g.angle_jacobian.segment(o, k) = p.angle_jacobian;
  g.angle_jacobian_dot_qdot = p.angle_jacobian_dot_qdot;
  return g;
}

void Linkage::add_revolute_rows(const Revolute& j, const Eigen::VectorXd& q,
                                const Eigen::VectorXd& qd, ConstraintRows& c, int row) const {
  const GlobalPoint a = point(j.a, q, qd), b = point(j.b, q, qd);
  c.value.segment<2>(row) = a.position - b.position;
  c.jacobian.middleRows(row, 2) = a.jacobian - b.jacobian;
  c.b1.segment<2>(row).setZero();
  c.b2.segment<2>(row) = a.jacobian_dot_qdot - b.jacobian_dot_qdot;
}

void Linkage::add_prismatic_rows(const Prismatic& j, const Eigen::VectorXd& q,
                                 const Eigen::VectorXd& qd, ConstraintRows& c, int row) const {
  const GlobalPoint a = point(j.a, q, qd), o = point(j.on_line, q, qd);
  const Eigen::Vector2d n(-j.axis.y(), j.axis.x());
  if (j.rows() == 2) {
    c.value[row] = n.dot(a.position - o.position);
    c.jacobian.row(row) = n.transpose() * a.jacobian;
    c.b1[row] = 0.0;
    c.b2[row] = n.dot(a.jacobian_dot_qdot);
    ++row;
  }
  c.value[row] = a.angle - j.angle;
  c.jacobian.row(row) = a.angle_jacobian;
  c.b1[row] = 0.0;
  c.b2[row] = a.angle_jacobian_dot_qdot;
  c.is_angle[static_cast<std::size_t>(row)] = true;
}

void Linkage::add_drive_rows(double t, const Drive& j, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& qd, ConstraintRows& c, int row) const {
  const GlobalPoint a = point(j.a, q, qd), r = point(j.rest, q, qd);
  const DriveSample d = j.law(t);
  if (j.rotary || j.guided) {  // one row: the section's angle, or the point along u
    const Eigen::Vector2d& u = j.direction;
    c.value[row] =
        j.rotary ? a.angle - j.angle0 - d.value : u.dot(a.position - r.position) - d.value;
    c.jacobian.row(row) = j.rotary ? a.angle_jacobian : u.transpose() * a.jacobian;
    c.b1[row] = -d.rate;
    c.b2[row] =
        (j.rotary ? a.angle_jacobian_dot_qdot : u.dot(a.jacobian_dot_qdot)) - d.acceleration;
    c.is_angle[static_cast<std::size_t>(row)] = j.rotary;
    return;
  }
  c.value.segment<2>(row) = a.position - r.position - d.value * j.direction;
  c.jacobian.middleRows(row, 2) = a.jacobian;
  c.b1.segment<2>(row) = -d.rate * j.direction;
  c.b2.segment<2>(row) = a.jacobian_dot_qdot - d.acceleration * j.direction;
}

ConstraintRows Linkage::constraints(double t, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& qd) const {
  const int m = constraint_count();
  ConstraintRows c;
  c.value.resize(m);
  c.b1.resize(m);
  c.b2.resize(m);
  c.jacobian = Eigen::MatrixXd::Zero(m, n_);
  c.is_angle.assign(static_cast<std::size_t>(m), false);
  int row = 0;
  for (const Revolute& j : revolutes_) add_revolute_rows(j, q, qd, c, (row += 2) - 2);
  for (const Prismatic& j : prismatics_)
    add_prismatic_rows(j, q, qd, c, (row += j.rows()) - j.rows());
  for (const Drive& j : drives_) add_drive_rows(t, j, q, qd, c, (row += j.rows()) - j.rows());
  add_rigid_rows(q, c, row);
  return c;
}

double Linkage::assemble(double t, Eigen::VectorXd& q, int iterations) const {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n_);
  double residual = 0.0;
  for (int k = 0; k <= iterations; ++k) {
    const ConstraintRows c = constraints(t, q, zero);
    residual = c.value.size() ? c.value.cwiseAbs().maxCoeff() : 0.0;
    if (residual < 1e-15 || k == iterations) break;
    q -= c.jacobian.completeOrthogonalDecomposition().solve(c.value);
  }
  return residual;
}

Eigen::VectorXd Linkage::consistent_velocity(double t, const Eigen::VectorXd& q) const {
  const ConstraintRows c = constraints(t, q, Eigen::VectorXd::Zero(n_));
  if (c.value.size() == 0) return Eigen::VectorXd::Zero(n_);
  return c.jacobian.completeOrthogonalDecomposition().solve(-c.b1);
}

}  // namespace rodend::linkage
