// Archard wear (issue 11): the maps conserve volume, the run's maps integrate to (k/H) times
// the sliding work the state integrates, a motion symmetric about the xy-plane wears
// symmetrically, the worn contact stays conservative, and the wear evolution converges in its
// update interval.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.hpp"
#include "fixture.hpp"
#include "sweep/runner.hpp"
#include "sweep/study.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

constexpr double kPi = std::numbers::pi;

Vec3 direction(double lon, double lat) {
  return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
}

/// Collects the wear a run deposits and the last sample's sliding work and energy audit.
class WearObserver final : public RunObserver {
 public:
  explicit WearObserver(const Scene& s) : acc_(*s.wear_model()) {}
  void on_wear(const WearSource& src, double w) override { acc_.add(src, w); }
  bool wants_wear() const override { return true; }
  void on_sample(const SignalFrame& f) override {
    sliding_work = f.get(SignalId::sliding_work);
    worn_volume = f.get(SignalId::worn_volume);
    residual = std::max(residual, std::abs(f.get(SignalId::energy_residual)));
    flow = std::max({flow, std::abs(f.get(SignalId::input_work)),
                     std::abs(f.get(SignalId::dissipated_energy))});
  }
  const WearAccumulator& wear() const { return acc_; }
  double sliding_work = 0.0, worn_volume = 0.0, residual = 0.0, flow = 0.0;

 private:
  WearAccumulator acc_;
};

/// The rod-end under a proportional hinge moment with a short full-stroke duty cycle (0.8 s):
/// the ball is loaded against the socket and slides on it for most of the cycle.
ParameterSet worn_rod_end(double misalignment_z = 0.0) {
  ParameterSet p = ParameterSet::defaults_for("rod-end-kinematic");
  p.set("wear.model", "archard");
  p.set("hinge.kind", "proportional");
  p.set("hinge.stiffness", 40.0);
  p.set("motion.extension", 0.05);  // +-50 mm, as studies/wear-evolution.json
  p.set("motion.retraction", 0.05);
  p.set("motion.extension_time", 0.3);
  p.set("motion.retraction_time", 0.3);
  p.set("motion.hold_time", 0.05);
  p.set("socket.misalignment_z", misalignment_z);
  return p;
}

constexpr double kCycleEnd = 0.7;  // 0.3 + 0.05 + 0.3 + 0.05 [s]

}  // namespace

TEST_CASE("wear map: a deposit adds exactly its volume, anywhere on the sphere", "[wear]") {
  WearMap m(0.01, 144, 72);
  double added = 0.0;
  // the equator, the longitude seam at +-180 deg, near a pole, and a patch wider than a cell
  const struct {
    double lon, lat, volume, patch;
  } deposits[] = {{0.3, 0.0, 1e-12, 0.05},         {kPi - 1e-3, 0.2, 2e-12, 0.1},
                  {-kPi + 1e-3, -0.2, 3e-12, 0.1}, {1.0, 0.5 * kPi - 0.01, 4e-12, 0.2},
                  {-2.0, -1.2, 5e-12, 0.01},       {0.0, 0.0, 6e-12, 0.6}};
  for (const auto& d : deposits) {
    m.deposit(direction(d.lon, d.lat), d.volume, d.patch);
    added += d.volume;
  }
  // only round-off: a sum over 1e4 cells of ~1e-12
  CHECK(m.volume() == Approx(added).epsilon(1e-12));
  // cell areas tile the sphere
  double area = 0.0;
  for (int j = 0; j < m.n_latitude(); ++j) area += m.cell_area(j) * m.n_longitude();
  CHECK(area == Approx(4.0 * kPi * 0.01 * 0.01).epsilon(1e-12));
  // reads never go below zero nor above the deepest cell (non-negative spline weights)
  const double deepest = m.max_depth().depth;
  for (int k = 0; k < 2000; ++k) {
    const double h =
        m.depth_at(direction(0.0031 * k * 7.0, std::asin(std::fmod(0.37 * k, 2.0) - 1.0)));
    CHECK(h >= 0.0);
    CHECK(h <= deepest * (1 + 1e-12));
  }
}

TEST_CASE("wear map: the deposit's centre is where the contact is, mirrored with it", "[wear]") {
  WearMap up(0.01, 144, 72), down(0.01, 144, 72);
  up.deposit(direction(0.7, 0.3), 1e-12, 0.08);
  down.deposit(direction(0.7, -0.3), 1e-12, 0.08);
  const auto e = up.max_depth();
  CHECK(e.longitude == Approx(0.7).margin(2.5 * kPi / 180));
  CHECK(e.latitude == Approx(0.3).margin(2.5 * kPi / 180));
  for (int j = 0; j < 72; ++j)
    for (int i = 0; i < 144; ++i) CHECK(up.depth(i, j) == down.depth(i, 71 - j));
  // and the interpolated depth's gradient points towards the centre of the patch
  Vec3 g;
  up.depth_at(direction(0.7 + 0.05, 0.3), &g);
  CHECK(g.dot(direction(0.7, 0.3) - direction(0.75, 0.3)) > 0.0);
}

TEST_CASE("wear: the maps hold (k/H) times the sliding work the state integrates", "[wear]") {
  const ParameterSet p = worn_rod_end();
  const auto scene = make_scene("rod-end-kinematic", p);
  REQUIRE(scene->wear_model());
  WearObserver obs(*scene);
  const RunResult r = simulate(*scene, dopri5(1e-8), TimeSettings{kCycleEnd, 1e-3}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(obs.sliding_work > 0.0);
  const WearModel& w = *scene->wear_model();
  const double vb = obs.wear().ball().volume(), vs = obs.wear().socket().volume();
  // the maps are filled by 3-point Gauss quadrature on each accepted step's interpolant, the
  // state by the method's own stages: two quadratures of the same F_N v_slip, each to ~tol
  measured("wear map volume vs (k/H) x sliding-work state",
           std::abs(vb / (w.ball.rate() * obs.sliding_work) - 1.0), 1e-6);
  CHECK(vb == Approx(w.ball.rate() * obs.sliding_work).epsilon(1e-6));
  CHECK(vs == Approx(w.socket.rate() * obs.sliding_work).epsilon(1e-6));
  // the accumulator's own sum of deposits, and the recorded worn-volume signal
  CHECK(obs.wear().sliding_work() == Approx(obs.sliding_work).epsilon(1e-6));
  CHECK(vb + vs == Approx(obs.worn_volume).epsilon(1e-6));
  // the socket is softer (H 3.9 vs 6.9 GPa): it loses more material
  CHECK(vs > vb);
}

TEST_CASE("wear: a motion symmetric about the xy-plane wears symmetric maps", "[wear]") {
  // no misalignment: the mechanism moves in the xy-plane (gravity along -y), so every contact
  // direction lies in the plane and the maps must be mirror images of themselves about the
  // equator; with a misalignment of +z and -z the two runs mirror each other
  auto maps = [](double z) {
    const auto scene = make_scene("rod-end-kinematic", worn_rod_end(z));
    WearObserver obs(*scene);
    const RunResult r = simulate(*scene, dopri5(1e-8), TimeSettings{kCycleEnd, 1e-3}, obs);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::ok);
    return std::make_pair(obs.wear().ball(), obs.wear().socket());
  };
  auto mirror_error = [](const WearMap& a, const WearMap& b) {
    double err = 0.0;
    const int n = a.n_latitude();
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < a.n_longitude(); ++i)
        err = std::max(err, std::abs(a.depth(i, j) - b.depth(i, n - 1 - j)));
    return err / std::max(a.max_depth().depth, 1e-300);
  };
  const auto [ball, socket] = maps(0.0);
  REQUIRE(ball.max_depth().depth > 0.0);
  REQUIRE(socket.max_depth().depth > 0.0);
  // exactly planar: the z components stay 0, the cell rows mirror bit for bit
  CHECK(mirror_error(ball, ball) == 0.0);
  CHECK(mirror_error(socket, socket) == 0.0);

  const auto [ball_up, socket_up] = maps(1e-4);
  const auto [ball_down, socket_down] = maps(-1e-4);
  // mirror-image runs: the same arithmetic with z negated, so equal to round-off
  CHECK(mirror_error(ball_up, ball_down) < 1e-9);
  CHECK(mirror_error(socket_up, socket_down) < 1e-9);
  // and out of the plane: the misaligned runs wear off the equator
  CHECK(mirror_error(socket_up, socket_up) > 1e-3);
}

TEST_CASE("wear: the contact on worn surfaces is conservative", "[wear]") {
  // a deep, narrow worn patch on both bodies where the ball rides: the normal force acts along
  // the gradient of the penetration, so the elastic contact does no net work; with a law
  // without damping and no friction, the energy audit closes to the integration tolerance
  ParameterSet p = worn_rod_end();
  p.set("contact.law", "hertz");
  p.set("friction.law", "none");
  const auto base = make_scene("rod-end-kinematic", p);
  auto worn = std::make_shared<WornSurfaces>();
  const WearModel& w = *base->wear_model();
  worn->ball = WearMap(w.ball_radius, w.n_longitude, w.n_latitude);
  worn->socket = WearMap(w.socket_radius, w.n_longitude, w.n_latitude);
  for (double lon = -kPi; lon < kPi; lon += 0.02) {
    // 0 to 40 um deep, varying with longitude: the surfaces are far from spherical
    worn->ball.deposit(direction(lon, 0.0), 2e-12 * (1.0 + std::sin(3.0 * lon)), 0.05);
    worn->socket.deposit(direction(lon, 0.0), 2e-12 * (1.0 + std::cos(5.0 * lon)), 0.05);
  }
  REQUIRE(worn->socket.max_depth().depth > 1e-6);
  const auto scene = base->with_worn_surfaces(worn);
  WearObserver obs(*scene);
  const RunResult r = simulate(*scene, dopri5(1e-10), TimeSettings{kCycleEnd, 1e-3}, obs);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  // relative to the largest flow (input work or dissipation); measured 4e-9
  measured("worn contact energy residual", obs.residual / obs.flow, 1e-6);
  CHECK(obs.residual / obs.flow < 1e-6);
}

TEST_CASE("wear evolution: halving the update interval changes cycles-to-limit by < 2 %",
          "[wear][evolution]") {
  // the short duty cycle, with a large wear coefficient so the limit (10 um of axial
  // clearance) comes within a few updates; the adaptive rule sets the interval (at most 20 or
  // 10 um of new depth per update)
  auto study = [](double depth_change) {
    Json doc = {
        {"name", "wear-test"},
        {"scene", "rod-end-kinematic"},
        {"parameters",
         {{"wear",
           {{"model", "archard"}, {"ball_coefficient", 1e-3}, {"socket_coefficient", 1e-3}}},
          {"hinge", {{"kind", "proportional"}, {"stiffness", 40.0}}},
          {"motion",
           {{"extension", 0.05},
            {"retraction", 0.05},
            {"extension_time", 0.3},
            {"retraction_time", 0.3},
            {"hold_time", 0.05}}}}},
        {"integrator", {{"preset", "fast"}}},
        {"time", {{"end", kCycleEnd}, {"sample_interval", 1e-2}}},
        {"signals", Json::array({"contact_force"})},
        {"wear_evolution",
         {{"cycles_per_update", 1e6},
          {"max_depth_change", depth_change},
          {"clearance_limit", 5.1e-4},
          {"max_updates", 200}}}};
    return parse_study(doc, "wear-test.json", "/tmp/rodend-results");
  };
  auto cycles_to_limit = [](const Study& s, long& updates) {
    History h;
    const CaseRecord r = run_case(s.cases.at(0), h);
    INFO(r.message);
    REQUIRE(r.status == RunStatus::ok);
    updates = static_cast<long>(r.metrics[static_cast<std::size_t>(MetricId::wear_updates)]);
    // the evolution's axial clearance grows monotonically from the nominal clearance
    for (const CaseArray& a : h.arrays)
      if (a.group == "evolution" && a.name == "axial_clearance") {
        CHECK(a.values.front() == Approx(5e-4));
        for (std::size_t k = 1; k < a.values.size(); ++k) CHECK(a.values[k] >= a.values[k - 1]);
      }
    return r.metrics[static_cast<std::size_t>(MetricId::cycles_to_limit)];
  };
  long n1 = 0, n2 = 0;
  const double c1 = cycles_to_limit(study(2e-5), n1);
  const double c2 = cycles_to_limit(study(1e-5), n2);
  REQUIRE(std::isfinite(c1));
  REQUIRE(std::isfinite(c2));
  CHECK(n2 > n1);
  measured("cycles-to-limit change on halving the update interval", std::abs(c1 - c2) / c2, 0.02);
  CHECK(std::abs(c1 - c2) / c2 < 0.02);
}

TEST_CASE("wear evolution: a scene without a wear model is refused by name", "[wear][study]") {
  Json doc = {{"name", "x"},
              {"scene", "rod-end-kinematic"},
              {"time", {{"end", 0.1}, {"sample_interval", 1e-2}}},
              {"wear_evolution", {{"clearance_limit", 6e-4}}}};
  try {
    parse_study(doc, "x.json", "/tmp/rodend-results");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("parameters.wear.model") != std::string::npos);
  }
  doc["parameters"] = {{"wear", {{"model", "archard"}}}};
  doc["wear_evolution"] = {{"cycles_per_update", -1.0}};
  CHECK_THROWS_WITH(parse_study(doc, "x.json", "/tmp/rodend-results"),
                    Catch::Contains("wear_evolution.cycles_per_update"));
}
