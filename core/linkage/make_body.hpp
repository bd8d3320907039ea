#pragma once
// The factory of the linkage's bodies from their part description (docs/planar-linkage.md):
// `<prefix>.kind` names the kind, the other keys under `<prefix>` are the kind's.
#include <memory>
#include <string>
#include <vector>

#include "core/linkage/body.hpp"
#include "core/params.hpp"

namespace rodend::linkage {

/// The body under `prefix` with its material points `point_names` (keys under
/// `<prefix>.points`, body frame [m]) in that order. Throws InputError naming the key.
std::unique_ptr<Body> make_body(const ParameterSet& p, const std::string& prefix,
                                const std::vector<std::string>& point_names);

/// A point `<prefix>` of the plane: a 3-vector [m] whose z is 0 (InputError otherwise).
Eigen::Vector2d read_plane_point(const ParameterSet& p, const std::string& path);

}  // namespace rodend::linkage
