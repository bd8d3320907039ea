#pragma once
// The planar linkage read from its parameters (the part files of docs/planar-linkage.md):
// bodies under linkage.bodies.<name>, ground points under linkage.ground.<name>, joints under
// linkage.joints.<name>, the actuator under linkage.actuator and its motion under motion, the
// clearance joints' contact and friction laws under contact and friction. Every group present
// is read, in name order: a fifth body or joint is a new group in a part file.
#include <string>
#include <vector>

#include "core/linkage/assembly.hpp"
#include "core/linkage/linkage_choices.hpp"
#include "core/params.hpp"
#include "core/scenes/drivers.hpp"

namespace rodend::linkage {

struct LinkageModel {
  Linkage linkage;                                 ///< finished (ideal() built)
  std::vector<std::string> body_names;             ///< in body order
  std::vector<std::string> clearance_joint_names;  ///< in clearance-joint order
  Eigen::VectorXd initial_guess;                   ///< the bodies' origin and angle, modes 0
  PointRef output;                                 ///< linkage.output: the shaft's point
  InputPtr motion;                                 ///< the actuator's displacement
  LinkageDrive drive = LinkageDrive::linear;       ///< linkage.actuator.kind
  PointRef actuator;                               ///< linkage.actuator.point
  double crank_speed = 0.0;   ///< linkage.actuator.speed of a crank_speed drive [rad/s]
  double drive_radius = 0.0;  ///< a rotary drive's body's radius (body_radius) [m]
  PointRef slider{-2, 0};     ///< the first prismatic guide's point (body -2: none)
  Eigen::Vector2d slider_axis = Eigen::Vector2d::UnitX();  ///< and its direction
  double length_scale = 0.0;        ///< the smallest clearance, else 0.1 mm [m] (state scales)
  std::vector<double> body_radius;  ///< largest point distance from each body's origin [m]
};

/// Throws InputError naming the key path.
LinkageModel read_linkage(const ParameterSet& p);

/// The names of the groups directly under `prefix` (sorted).
std::vector<std::string> parameter_groups(const ParameterSet& p, const std::string& prefix);

}  // namespace rodend::linkage
