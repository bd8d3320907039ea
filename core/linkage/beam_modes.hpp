#pragma once
// The free vibration modes of a straight, piecewise uniform planar beam: the reduction basis of a
// flexible body of the planar linkage (core/linkage/flexible_body.hpp, docs/flexible-bodies.md).
//
// Finite elements along the beam's axis (its local s from 0 to the length L [m]): Euler-Bernoulli
// bending elements (transverse v and slope dv/ds at each node, Hermite cubics) and bar elements
// (axial u, linear), each with its consistent mass matrix. Bending and axial motion are
// uncoupled in a straight beam, so each is its own generalised eigenproblem K phi = omega^2 M phi
// (Eigen's GeneralizedSelfAdjointEigenSolver), and a mode is either bending or axial. Modes are
// mass-normalised (phi^T M phi = 1 [kg^-1/2 per unit of amplitude]) and signed so that their
// largest nodal displacement is positive.
//
// The boundary conditions are those of the reduction, i.e. the floating frame's definition
// (each removes exactly the beam's three planar rigid-body motions):
//   free_free     no support; the elastic modes are mass-orthogonal to the rigid motions, so
//                 the frame is the beam's mean axis (Tisserand frame, to first order);
//   pinned_pinned u(0) = v(0) = v(L) = 0: the frame's origin at the end s = 0 and its x-axis
//                 through both ends (the chord frame); axial motion is that of a bar fixed at
//                 s = 0 and free at s = L;
//   clamped_free  u(0) = v(0) = v'(0) = 0: the frame is tangent to the beam at s = 0.
// Alternatively the modes may be given directly (frequencies and nodal shapes on a mesh).
#include "core/choice.hpp"

#include <vector>

#include <Eigen/Dense>

namespace rodend {
/// The boundary conditions of the reduction (core/linkage/beam_supports.def).
#define RODEND_CHOICE_ENUM BeamSupport
#define RODEND_CHOICE_FILE "core/linkage/beam_supports.def"
#include "core/choice.hpp"
}  // namespace rodend

namespace rodend::linkage {

using rodend::BeamSupport;

/// One piece of uniform section along the beam.
struct BeamSegment {
  double length = 0.0;         ///< [m]
  double area = 0.0;           ///< cross-section area [m^2]
  double second_moment = 0.0;  ///< area moment about the bending axis (normal to the plane) [m^4]
};

struct BeamMaterial {
  double youngs_modulus = 0.0;  ///< [Pa]
  double density = 0.0;         ///< [kg/m^3]
};

/// A mode's displacement of the beam's axis at one station: axial u, transverse v, and the
/// cross-section's rotation dv/ds, per unit amplitude.
struct ModeShapeAt {
  double axial = 0.0;       ///< u
  double transverse = 0.0;  ///< v
  double slope = 0.0;       ///< dv/ds [1/m per unit of the shape's unit]
};

class BeamModes {
 public:
  /// What the finite-element reduction needs.
  struct Spec {
    std::vector<BeamSegment> segments;
    BeamMaterial material;
    BeamSupport support = BeamSupport::free_free;
    int bending_modes = 1;
    int axial_modes = 0;
    int elements = 40;  ///< elements along the whole beam (at least one per segment)
  };
  /// The first spec.bending_modes bending and spec.axial_modes axial elastic modes, in
  /// increasing frequency. Throws std::invalid_argument on a non-positive dimension or
  /// material value, or more modes than the mesh has.
  static BeamModes compute(const Spec& spec);
  /// Modes given directly: node stations s [m] (increasing, from 0), mass per length of each
  /// element [kg/m] (one fewer than the nodes), angular frequencies [rad/s], and per mode its
  /// nodal values (u, v, dv/ds at each node: 3 x nodes). The shapes are used as given.
  static BeamModes given(std::vector<double> nodes, std::vector<double> mass_per_length,
                         std::vector<double> frequencies, std::vector<Eigen::VectorXd> shapes);

  int count() const { return static_cast<int>(omega_.size()); }
  double frequency(int mode) const { return omega_[static_cast<std::size_t>(mode)]; }  ///< rad/s
  bool is_axial(int mode) const { return axial_[static_cast<std::size_t>(mode)]; }
  double length() const { return nodes_.back(); }  ///< [m]
  /// Mode `mode` at station s (0 <= s <= length()), interpolated by the element's functions.
  ModeShapeAt at(int mode, double s) const;
  /// Mesh: node stations [m], each element's mass per length [kg/m] and rotary inertia per
  /// length rho I [kg m] (of the cross-sections, for the rigid body's inertia).
  const std::vector<double>& nodes() const { return nodes_; }
  const std::vector<double>& mass_per_length() const { return rho_a_; }
  const std::vector<double>& rotary_inertia_per_length() const { return rho_i_; }
  /// Nodal values of mode `mode` (3 per node: u, v, dv/ds).
  const Eigen::VectorXd& shape(int mode) const { return shapes_[static_cast<std::size_t>(mode)]; }
  /// Scales mode `mode`'s shape by `factor` (its amplitude then scales by 1/factor).
  void scale(int mode, double factor) { shapes_[static_cast<std::size_t>(mode)] *= factor; }

 private:
  std::vector<double> nodes_, rho_a_, rho_i_, omega_;
  std::vector<bool> axial_;
  std::vector<Eigen::VectorXd> shapes_;
};

}  // namespace rodend::linkage
