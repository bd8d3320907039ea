// The length on which the error norm measures the positions of a rod-end's ball and socket
// (their share of Scene::state_scale): one fixed length, the same for every clearance.
#pragma once

namespace rodend {

/// [m] The order of the rod-end contact's Hertz approach at the loads its metrics are about:
/// delta = (F / K)^(1/n) is 3.5-7.4 um at 1 kN and 9-19 um at 4.2 kN (the largest contact force
/// of the loaded thesis cycles) over clearances of 0.1-1 mm (K = 4/3 E* sqrt(R*) of the default
/// steel ball of 10 mm radius, n = 1.5; docs/model.md "Error norm"). A position error of
/// tol x 10 um is then about tol of the approach, so n x tol of the contact force.
///
/// Why not the clearance (the scale until 2026-11-28): a scale that follows the clearance weighs
/// the same free flight differently in each case, so cases that differ only in clearance took
/// different steps before any contact and their motions disagreed by about the tolerance there
/// (the socket's speed by 4e-5 at cvode_bdf 1e-6 between 0.2, 0.5 and 1 mm). With one length
/// they take the same steps until the first contact and agree to the last bit at any
/// tolerance. Not the Hertz approach computed from the case's own stiffness either: K depends
/// on the clearance through R* = R_b R_s / c.
constexpr double contact_length_scale() {
  return 10e-6;
}

}  // namespace rodend
