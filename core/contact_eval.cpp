// The double instances of the clearance contact's force pipeline (core/contact_eval.hpp):
// the functions of core/contact.hpp that evaluate it.
#include "core/contact_eval.hpp"

namespace rodend {

double elastic_force(const ClearanceContactModel& m, double delta) {
  return contact_detail::elastic_force(m, delta);
}

ContactGap contact_gap(const ClearanceContactModel& m, const BodyKinematics& ball,
                       const BodyKinematics& socket) {
  const auto p = contact_detail::penetration(m, ball, socket);
  if (p.centred) return {-p.clearance, 0.0};
  ContactGap g{p.value(), p.rate(ball, socket)};
  if ((m.branches.stuck || m.stick) && g.penetration > 0.0) {  // stick-slip, switch: the branch
    g.slipping = contact_detail::slip_velocity(m, ball, socket, p.normal).norm() > m.switch_speed;
    g.stick = m.stick;
  }
  return g;
}

ContactEval evaluate_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                             const BodyKinematics& socket, const ContactLatch& latch) {
  return contact_detail::evaluate(m, ball, socket, latch);
}

ContactEval evaluate_normal_contact(const ClearanceContactModel& m, const BodyKinematics& ball,
                                    const BodyKinematics& socket, const ContactLatch& latch) {
  return contact_detail::evaluate<double, false>(m, ball, socket, latch);
}

}  // namespace rodend
