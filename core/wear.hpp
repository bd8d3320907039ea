// Archard wear of the clearance contact: wear maps on the ball and the socket (docs/wear.md).
//
// The thesis stops at a wear indicator F_N v_slip (thesis §5.1). Archard's law turns it into a
// worn-volume rate for each body:
//     dV/dt = (k / H) F_N v_slip          k: wear coefficient [-], H: hardness [Pa]
// Each body has its own k and H (a hard ball in a softer race wears less than the race).
// The volume leaves each body where the contact is in that body's own frame: the socket loses
// material where the ball rides on it, the ball where the socket rubs it. It is spread over the
// Hertz contact patch (radius a = sqrt(R* delta), R* the conformal radius of model-notes §1),
// with the Hertz pressure's profile sqrt(1 - r^2/a^2) (the local Archard rate is proportional to
// the pressure), so the map records depth, not a single cell's worth of volume.
//
// A map is worn depth [m] over an equal-angle grid of surface directions of one body, in that
// body's frame: longitude phi in [-pi, pi) about the body z axis from +x, latitude lambda in
// [-pi/2, pi/2] from the xy-plane. A cell's area on the sphere of radius R is
// R^2 dphi (sin lambda_top - sin lambda_bottom), so sum(depth x area) is the worn volume (thin
// layer: depths are micrometres on a ~10 mm sphere).
//
// Geometry (WornSurfaces): the contact reads the local clearance in the contact direction n,
//     c(n) = c0 + h_ball(R_ball^T n) + h_socket(R_socket^T n),
// from maps that are fixed for a whole run (they change only between wear updates, so the
// right-hand side is smooth: each map is read through a C1 quadratic B-spline, whose weights are
// non-negative, so a read depth is never negative and never overshoots the cells around it). The
// maps used for the geometry are the accumulated wear of previous updates; the maps a run deposits
// into are separate (WearAccumulator).
#pragma once

#include <memory>
#include <vector>

#include "core/choice.hpp"
#include "core/math.hpp"

namespace rodend {

/// Archard constants of one body.
struct WearMaterial {
  double coefficient = 0.0;                               ///< Archard wear coefficient k [-]
  double hardness = 1.0;                                  ///< indentation hardness H [Pa]
  double rate() const { return coefficient / hardness; }  ///< k/H [1/Pa = m^3/J]
};

/// A wear map: worn depth [m] over a grid of directions of one body's surface (body frame).
class WearMap {
 public:
  WearMap() = default;
  /// `radius` of the worn sphere [m]; n_longitude x n_latitude equal-angle cells.
  WearMap(double radius, int n_longitude, int n_latitude);

  int n_longitude() const { return n_lon_; }
  int n_latitude() const { return n_lat_; }
  double radius() const { return radius_; }
  bool empty() const { return depth_.empty(); }

  /// Cell centres [rad].
  double longitude(int i) const;
  double latitude(int j) const;
  /// Area of a cell of latitude row j on the sphere [m^2].
  double cell_area(int j) const;
  /// Depth of cell (i longitude, j latitude) [m]; row-major by latitude (j * n_lon + i).
  double depth(int i, int j) const { return depth_[static_cast<std::size_t>(j * n_lon_ + i)]; }
  const std::vector<double>& depths() const { return depth_; }

  /// Worn volume, sum of depth x cell area [m^3].
  double volume() const;
  /// Deepest cell: its depth [m] and its centre's longitude and latitude [rad].
  struct Extreme {
    double depth = 0.0, longitude = 0.0, latitude = 0.0;
  };
  Extreme max_depth() const;

  /// Removes `volume` [m^3] around the unit direction `dir_B` (body frame), spread over a patch
  /// of angular radius `patch_angle` [rad] with weights sqrt(1 - (theta/patch)^2) x cell area,
  /// normalised so that exactly `volume` is added to volume(). Patches narrower than the grid
  /// are widened to one cell (the map cannot resolve them).
  void deposit(const Vec3& dir_B, double volume, double patch_angle);

  /// Depth at the unit direction `dir_B` by a C1 quadratic B-spline over the cells [m] (a
  /// smoothing of the cell values, never below the smallest nor above the largest), and its
  /// gradient with respect to the direction, a tangent vector in the body frame [m/rad].
  double depth_at(const Vec3& dir_B, Vec3* gradient_B = nullptr) const;

  /// this += s * other (same grid).
  void add_scaled(const WearMap& other, double s);
  /// Whether two maps share radius and grid.
  static bool same_grid(const WearMap& a, const WearMap& b);

 private:
  double radius_ = 0.0;
  int n_lon_ = 0, n_lat_ = 0;
  double dlon_ = 0.0, dlat_ = 0.0;
  std::vector<double> depth_;
  std::vector<double> area_;  ///< per latitude row [m^2]
};

/// The worn geometry a run sees: the accumulated wear of both bodies, fixed for the run.
struct WornSurfaces {
  WearMap ball, socket;
  /// Local clearance increase h_ball(R_b^T n) + h_socket(R_s^T n) in the world direction n [m],
  /// and its gradients with respect to n, each rotated to the world frame [m/rad].
  double extra_clearance(const Vec3& n_W, const Mat3& R_ball, const Mat3& R_socket,
                         Vec3* grad_ball_W = nullptr, Vec3* grad_socket_W = nullptr) const;
};

/// Wear model of a clearance contact (immutable).
/// The wear models (wear.model), from core/wear_models.def.
#define RODEND_CHOICE_ENUM WearModelKind
#define RODEND_CHOICE_FILE "core/wear_models.def"
#include "core/choice.hpp"

struct WearModel {
  WearMaterial ball, socket;
  double ball_radius = 0.0, socket_radius = 0.0;  ///< radii of the worn spheres [m]
  int n_longitude = 144, n_latitude = 72;         ///< map grid [-]
  /// The worn geometry (null: as manufactured).
  std::shared_ptr<const WornSurfaces> worn;
};

/// What the contact wears at one instant: the sliding power and where it acts.
struct WearSource {
  double sliding_power = 0.0;               ///< F_N v_slip, the thesis's wear indicator [W]
  Vec3 direction_ball_B = Vec3::UnitX();    ///< contact direction in the ball's frame
  Vec3 direction_socket_B = Vec3::UnitX();  ///< contact direction in the socket's frame
  double patch_radius = 0.0;                ///< Hertz contact radius a [m]
};

/// Deposits the wear of a run into fresh maps (one per body).
///
/// Consecutive sources whose contact directions stay within a tenth of a cell (on both bodies)
/// and whose patch radius stays within 10 % are lumped into one deposit at their work-weighted
/// mean direction and patch: the volume is exact, the place is off by at most a tenth of a
/// cell, and a run of millions of tiny steps (resting contact, stick-slip) costs a few
/// thousand deposits instead of millions.
class WearAccumulator {
 public:
  explicit WearAccumulator(const WearModel& model);
  /// Adds the wear of `source` acting for `duration` [s].
  void add(const WearSource& source, double duration);
  /// The maps, everything added so far deposited.
  const WearMap& ball() const;
  const WearMap& socket() const;
  /// Integral of F_N v_slip added so far [J].
  double sliding_work() const { return sliding_work_; }

 private:
  struct Lump {
    double work = 0.0;                                              ///< [J]
    Vec3 ball_sum = Vec3::Zero(), socket_sum = Vec3::Zero();        ///< work-weighted directions
    double patch_sum = 0.0;                                         ///< work-weighted patch [J m]
    Vec3 ball_first = Vec3::UnitX(), socket_first = Vec3::UnitX();  ///< first directions
    double patch_first = 0.0;
  };
  void flush() const;

  WearMaterial ball_material_, socket_material_;
  mutable WearMap ball_, socket_;
  mutable Lump lump_;
  double lump_cos_ = 1.0;  ///< cosine of the lumping angle
  double sliding_work_ = 0.0;
};

}  // namespace rodend
