#include "core/wear.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace rodend {

namespace {

constexpr double kPi = std::numbers::pi;

/// Quadratic B-spline weights of the three taps around the nearest node (t = offset from it,
/// in [-1/2, 1/2]) and their derivatives: non-negative, summing to 1, C1 across cells.
void quadratic_bspline(double t, double w[3], double dw[3]) {
  w[0] = 0.5 * (0.5 - t) * (0.5 - t);
  w[1] = 0.75 - t * t;
  w[2] = 0.5 * (0.5 + t) * (0.5 + t);
  dw[0] = -(0.5 - t);
  dw[1] = -2.0 * t;
  dw[2] = 0.5 + t;
}

}  // namespace

WearMap::WearMap(double radius, int n_longitude, int n_latitude)
    : radius_(radius), n_lon_(n_longitude), n_lat_(n_latitude) {
  if (!(radius > 0.0) || n_longitude < 4 || n_latitude < 2)
    throw std::invalid_argument(
        "wear map: need a radius > 0, >= 4 longitude and >= 2 latitude cells");
  dlon_ = 2.0 * kPi / n_lon_;
  dlat_ = kPi / n_lat_;
  depth_.assign(static_cast<std::size_t>(n_lon_) * static_cast<std::size_t>(n_lat_), 0.0);
  area_.resize(static_cast<std::size_t>(n_lat_));
  for (int j = 0; j < n_lat_; ++j)
    area_[static_cast<std::size_t>(j)] =
        radius_ * radius_ * dlon_ *
        (std::sin(latitude(j) + 0.5 * dlat_) - std::sin(latitude(j) - 0.5 * dlat_));
}

// centres written as (index + 1/2 - n/2) x spacing: exactly antisymmetric about 0, so a map is
// mirrored cell for cell about the equator (and about longitude 0)
double WearMap::longitude(int i) const {
  return (i + 0.5 - 0.5 * n_lon_) * dlon_;
}
double WearMap::latitude(int j) const {
  return (j + 0.5 - 0.5 * n_lat_) * dlat_;
}
double WearMap::cell_area(int j) const {
  return area_[static_cast<std::size_t>(j)];
}

double WearMap::volume() const {
  double v = 0.0;
  for (int j = 0; j < n_lat_; ++j) {
    double row = 0.0;
    for (int i = 0; i < n_lon_; ++i) row += depth(i, j);
    v += row * cell_area(j);
  }
  return v;
}

WearMap::Extreme WearMap::max_depth() const {
  Extreme e;
  for (int j = 0; j < n_lat_; ++j)
    for (int i = 0; i < n_lon_; ++i)
      if (depth(i, j) > e.depth) e = {depth(i, j), longitude(i), latitude(j)};
  return e;
}

void WearMap::deposit(const Vec3& dir_B, double volume, double patch_angle) {
  if (!(volume > 0.0)) return;
  const Vec3 d = dir_B.normalized();
  const double lat0 = std::asin(std::clamp(d.z(), -1.0, 1.0));
  const double lon0 = std::atan2(d.y(), d.x());
  const double alpha = std::max(patch_angle, std::max(dlat_, dlon_));
  const double cos_alpha = std::cos(alpha);
  // rows within alpha of the centre; longitudes within the patch's half-width at lat0 (all of
  // them when the patch reaches a pole)
  const int j_lo =
      std::max(0, static_cast<int>(std::floor((lat0 - alpha) / dlat_ + 0.5 * n_lat_)) - 1);
  const int j_hi =
      std::min(n_lat_ - 1, static_cast<int>(std::floor((lat0 + alpha) / dlat_ + 0.5 * n_lat_)) + 1);
  int i_half = n_lon_;
  if (std::abs(lat0) + alpha < 0.5 * kPi - dlat_) {
    const double half =
        std::asin(std::min(1.0, std::sin(alpha) / std::cos(std::abs(lat0) + alpha)));
    i_half = std::min(n_lon_, static_cast<int>(std::ceil(half / dlon_)) + 1);
  }
  const int i_mid = static_cast<int>(std::floor(lon0 / dlon_ + 0.5 * n_lon_));
  const int i_first = i_half >= n_lon_ / 2 ? 0 : i_mid - i_half;
  const int i_last = i_half >= n_lon_ / 2 ? n_lon_ - 1 : i_mid + i_half;

  // weights: Hertz pressure profile x cell area
  struct Cell {
    std::size_t k;
    double w;
  };
  thread_local std::vector<Cell> cells;
  cells.clear();
  double total = 0.0;
  for (int j = j_lo; j <= j_hi; ++j) {
    const double cl = std::cos(latitude(j)), sl = std::sin(latitude(j));
    for (int ii = i_first; ii <= i_last; ++ii) {
      const int i = ((ii % n_lon_) + n_lon_) % n_lon_;
      const double lon = longitude(i);
      const double c = cl * std::cos(lon) * d.x() + cl * std::sin(lon) * d.y() + sl * d.z();
      if (c <= cos_alpha) continue;
      const double theta = std::acos(std::min(1.0, c));
      const double r = theta / alpha;
      const double w = std::sqrt(std::max(0.0, 1.0 - r * r)) * cell_area(j);
      if (w <= 0.0) continue;
      cells.push_back({static_cast<std::size_t>(j * n_lon_ + i), w});
      total += w;
    }
  }
  if (!(total > 0.0)) {  // cannot happen with alpha >= one cell; kept so no volume is lost
    const int j =
        std::clamp(static_cast<int>(std::floor(lat0 / dlat_ + 0.5 * n_lat_)), 0, n_lat_ - 1);
    const int i = ((i_mid % n_lon_) + n_lon_) % n_lon_;
    depth_[static_cast<std::size_t>(j * n_lon_ + i)] += volume / cell_area(j);
    return;
  }
  // depth w / total x volume / area: sum(depth x area) = volume
  for (const Cell& c : cells) {
    const int j = static_cast<int>(c.k / static_cast<std::size_t>(n_lon_));
    depth_[c.k] += volume * (c.w / total) / cell_area(j);
  }
}

double WearMap::depth_at(const Vec3& dir_B, Vec3* gradient_B) const {
  const Vec3 d = dir_B.normalized();
  const double lat = std::asin(std::clamp(d.z(), -1.0, 1.0));
  const double lon = std::atan2(d.y(), d.x());
  const double u = lon / dlon_ + 0.5 * n_lon_ - 0.5;
  const double v = lat / dlat_ + 0.5 * n_lat_ - 0.5;
  const int i0 = static_cast<int>(std::lround(u)), j0 = static_cast<int>(std::lround(v));
  double wu[3], dwu[3], wv[3], dwv[3];
  quadratic_bspline(u - i0, wu, dwu);
  quadratic_bspline(v - j0, wv, dwv);
  double h = 0.0, h_lon = 0.0, h_lat = 0.0;
  for (int b = 0; b < 3; ++b) {
    const int j = std::clamp(j0 - 1 + b, 0, n_lat_ - 1);  // flat beyond the last rows
    for (int a = 0; a < 3; ++a) {
      const int i = (((i0 - 1 + a) % n_lon_) + n_lon_) % n_lon_;
      const double z = depth(i, j);
      h += wu[a] * wv[b] * z;
      h_lon += dwu[a] * wv[b] * z;
      h_lat += wu[a] * dwv[b] * z;
    }
  }
  if (gradient_B) {
    h_lon /= dlon_;
    h_lat /= dlat_;
    // per radian of surface arc: 1/cos(lat) along a parallel, bounded at the polar rows
    const double cl = std::max(std::cos(lat), std::sin(0.5 * dlat_));
    const Vec3 e_lon(-std::sin(lon), std::cos(lon), 0.0);
    const Vec3 e_lat(-std::sin(lat) * std::cos(lon), -std::sin(lat) * std::sin(lon), std::cos(lat));
    *gradient_B = (h_lon / cl) * e_lon + h_lat * e_lat;
  }
  return h;
}

void WearMap::add_scaled(const WearMap& other, double s) {
  if (!same_grid(*this, other)) throw std::invalid_argument("wear maps on different grids");
  for (std::size_t k = 0; k < depth_.size(); ++k) depth_[k] += s * other.depth_[k];
}

bool WearMap::same_grid(const WearMap& a, const WearMap& b) {
  return a.n_lon_ == b.n_lon_ && a.n_lat_ == b.n_lat_ && a.radius_ == b.radius_;
}

double WornSurfaces::extra_clearance(const Vec3& n_W, const Mat3& R_ball, const Mat3& R_socket,
                                     Vec3* grad_ball_W, Vec3* grad_socket_W) const {
  Vec3 gb = Vec3::Zero(), gs = Vec3::Zero();
  const double hb = ball.empty() ? 0.0 : ball.depth_at(R_ball.transpose() * n_W, &gb);
  const double hs = socket.empty() ? 0.0 : socket.depth_at(R_socket.transpose() * n_W, &gs);
  if (grad_ball_W) *grad_ball_W = R_ball * gb;
  if (grad_socket_W) *grad_socket_W = R_socket * gs;
  return hb + hs;
}

WearAccumulator::WearAccumulator(const WearModel& model)
    : ball_material_(model.ball),
      socket_material_(model.socket),
      ball_(model.ball_radius, model.n_longitude, model.n_latitude),
      socket_(model.socket_radius, model.n_longitude, model.n_latitude) {
  const double cell = std::min(2.0 * kPi / model.n_longitude, kPi / model.n_latitude);
  lump_cos_ = std::cos(0.1 * cell);
}

void WearAccumulator::add(const WearSource& s, double duration) {
  const double work = s.sliding_power * duration;  // [J]
  if (!(work > 0.0)) return;
  sliding_work_ += work;
  const Vec3 db = s.direction_ball_B.normalized(), ds = s.direction_socket_B.normalized();
  const bool joins = lump_.work > 0.0 && db.dot(lump_.ball_first) >= lump_cos_ &&
                     ds.dot(lump_.socket_first) >= lump_cos_ &&
                     std::abs(s.patch_radius - lump_.patch_first) <= 0.1 * lump_.patch_first;
  if (!joins) {
    flush();
    lump_.ball_first = db;
    lump_.socket_first = ds;
    lump_.patch_first = s.patch_radius;
  }
  lump_.work += work;
  lump_.ball_sum += work * db;
  lump_.socket_sum += work * ds;
  lump_.patch_sum += work * s.patch_radius;
}

void WearAccumulator::flush() const {
  if (!(lump_.work > 0.0)) return;
  const double patch = lump_.patch_sum / lump_.work;
  ball_.deposit(lump_.ball_sum, ball_material_.rate() * lump_.work, patch / ball_.radius());
  socket_.deposit(lump_.socket_sum, socket_material_.rate() * lump_.work, patch / socket_.radius());
  lump_ = Lump{};
}

const WearMap& WearAccumulator::ball() const {
  flush();
  return ball_;
}
const WearMap& WearAccumulator::socket() const {
  flush();
  return socket_;
}

}  // namespace rodend
