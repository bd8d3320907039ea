// Every scene's Jacobian (Scene::jacobian) against central differences of its right-hand side,
// at states in free flight, in an impact (penetrating, approaching) and in loaded sticking
// contact (penetrating, sliding slower than friction.static_speed, under a load).
//
// The scenes that override jacobian() with an exact one (exact_jacobian()) are checked strictly;
// for the others the default is itself a difference quotient, so their check is weaker (it still
// catches a wrong state scale or a discontinuity): the test prints which is which.
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "fixture.hpp"

using namespace rodend;

namespace {

struct Probe {
  std::string kind;  ///< "free", "impact" or "sticking"
  double t = 0.0;
  std::vector<double> x;
  DiscreteState d;
};

/// The scene's parameters for the probes: the defaults, and for the rod-end scenes a constant
/// hinge moment of -100 N m (the hinge-moment study's first loaded case), under which the ball
/// sticks in its socket while the surface is held.
ParameterSet probe_parameters(std::string_view scene) {
  ParameterSet p = ParameterSet::defaults_for(scene);
  if (scene == "rod-end-kinematic" || scene == "rod-end-actuator") {
    p.set("hinge.kind", Json("constant"));
    p.set("hinge.constant_moment", Json(-100.0));
  }
  return p;
}

RunResult run_to(const Scene& scene, double end, RunObserver& obs) {
  IntegratorSettings s;
  s.method = IntegratorMethod::cvode_bdf;
  s.abs_tol = s.rel_tol = 1e-9;
  s.max_step = 1e-3;
  return simulate(scene, s, TimeSettings{end, end}, obs);
}

/// The latch the driver would hold at x: in contact when penetrating, the approach speed given
/// (or the current rate, at least the law's guard).
DiscreteState latch_at(const Scene& scene, const double* x, double impact_speed = 0.0) {
  DiscreteState d;
  d.contacts.resize(static_cast<std::size_t>(scene.contact_count()));
  for (int c = 0; c < scene.contact_count(); ++c) {
    const ContactGap g = scene.contact_gap(c, x);
    auto& l = d.contacts[static_cast<std::size_t>(c)];
    l.in_contact = g.penetration > 0.0;
    if (l.in_contact) l.impact_speed = std::max({impact_speed, std::abs(g.penetration_rate), 1e-3});
  }
  return d;
}

struct OnsetRecorder final : RunObserver {
  std::vector<double> onsets;
  void on_contact_onset(double t, int, double) override { onsets.push_back(t); }
};

/// A state just after the first contact onset, still approaching (an impact under way).
void find_impact(const Scene& scene, double span, std::vector<Probe>& out) {
  OnsetRecorder rec;
  run_to(scene, span, rec);
  for (double t_on : rec.onsets)
    for (double after : {2e-6, 1e-6, 5e-7}) {
      RunObserver none;
      const RunResult r = run_to(scene, t_on + after, none);
      if (r.status != RunStatus::ok) continue;
      const ContactGap g = scene.contact_gap(0, r.final_state.data());
      if (g.penetration > 1e-4 * scene.contact_clearance(0) && g.penetration_rate > 0.0) {
        out.push_back({"impact", t_on + after, r.final_state,
                       latch_at(scene, r.final_state.data(), g.penetration_rate)});
        return;
      }
    }
}

/// A free state and the loaded state sliding slowest, from runs to k span / 24.
void find_free_and_sticking(const Scene& scene, double span, std::vector<Probe>& out) {
  bool free_found = false;
  Probe sticking;
  double slowest = INFINITY;
  for (int k = 0; k <= 24; ++k) {
    const double end = span * k / 24.0;
    RunResult r;
    if (k == 0) {  // the initial state
      r.final_state.resize(static_cast<std::size_t>(scene.state_size()));
      scene.initial_state(r.final_state.data());
    } else {
      RunObserver none;
      r = run_to(scene, end, none);
      REQUIRE(r.status == RunStatus::ok);
    }
    const double* x = r.final_state.data();
    const DiscreteState d = latch_at(scene, x);
    const bool touching = scene.contact_count() > 0 && d.contacts[0].in_contact;
    if (!touching && !free_found &&
        (scene.contact_count() == 0 ||
         scene.contact_gap(0, x).penetration < -1e-3 * scene.contact_clearance(0))) {
      free_found = true;
      out.push_back({"free", end, r.final_state, d});
    }
    if (!touching) continue;
    SignalFrame f;
    scene.outputs(end, x, d, f);
    const double slip = f.get(SignalId::slip_speed), force = f.get(SignalId::contact_force);
    if (force > 10.0 && slip < slowest &&
        scene.contact_gap(0, x).penetration > 1e-4 * scene.contact_clearance(0)) {
      slowest = slip;
      sticking = {
          "sticking, slip " + std::to_string(slip) + " m/s, F_n " + std::to_string(force) + " N",
          end, r.final_state, d};
    }
  }
  if (slowest < 1e-3) out.push_back(sticking);  // below friction.static_speed's 1 mm/s
}

/// Central differences of derivatives() at the probe, increment 1e-7 of each state's scale.
std::vector<double> central_jacobian(const Scene& scene, const Probe& p, double rel_step) {
  const auto un = p.x.size();
  std::vector<double> scale(un), xp = p.x, fp(un), fm(un), Jc(un * un);
  scene.state_scale(scale.data());
  for (std::size_t j = 0; j < un; ++j) {
    const double h = rel_step * std::max(std::abs(p.x[j]), scale[j]);
    xp[j] = p.x[j] + h;
    scene.derivatives(p.t, xp.data(), p.d, fp.data());
    xp[j] = p.x[j] - h;
    scene.derivatives(p.t, xp.data(), p.d, fm.data());
    xp[j] = p.x[j];
    for (std::size_t i = 0; i < un; ++i) Jc[i * un + j] = (fp[i] - fm[i]) / (2 * h);
  }
  return Jc;
}

/// The probe's Jacobian against the central quotients, entry by entry in scaled variables.
void check_probe(const std::string& e_name, const Scene& s, const Probe& p) {
  const Scene* scene = &s;
  const auto un = p.x.size();
  std::vector<double> scale(un);
  scene->state_scale(scale.data());
  std::vector<double> J(un * un), f0(un);
  scene->derivatives(p.t, p.x.data(), p.d, f0.data());
  scene->jacobian(p.t, p.x.data(), p.d, J.data());
  // two central quotients, increments 1e-7 and 2e-7 of the state's scale: their difference
  // is three quarters of the larger's truncation error O(h^2 f''') plus the round-off of
  // both, O(eps |f| / h), so it bounds the reference's own error entry by entry
  const std::vector<double> J1 = central_jacobian(*scene, p, 1e-7);
  const std::vector<double> J2 = central_jacobian(*scene, p, 2e-7);
  // scaled variables z = x / scale (every entry in 1/s), each row against its largest entry
  auto scaled = [&](const std::vector<double>& M, std::size_t i, std::size_t j) {
    return M[i * un + j] * scale[j] / scale[i];
  };
  double largest = 0.0;
  for (std::size_t i = 0; i < un; ++i)
    for (std::size_t j = 0; j < un; ++j) largest = std::max(largest, std::abs(scaled(J1, i, j)));
  const bool exact = scene->exact_jacobian();
  for (std::size_t i = 0; i < un; ++i) {
    double row = 0.0;
    for (std::size_t j = 0; j < un; ++j) row = std::max(row, std::abs(scaled(J1, i, j)));
    // the exact Jacobian must agree within the reference's estimated error, 1e-6 of its
    // row and 1e-12 of the matrix's largest entry (round-off of terms of that size that
    // cancel in a row). The default forward differences carry a truncation error of order
    // sqrt(eps) of the scale times the second derivative, 1e-3 of the row (the earlier
    // test's bound), and a round-off of eps |f_i| / (sqrt(eps) scale_j): 1e-6 |f_i /
    // scale_i| in scaled terms, and 1e-9 of the largest entry
    const double rel = exact ? 1e-6 : 1e-3;
    const double floor =
        exact ? 1e-12 * largest : 1e-6 * std::abs(f0[i] / scale[i]) + 1e-9 * largest;
    for (std::size_t j = 0; j < un; ++j) {
      const double a = scaled(J, i, j), b = scaled(J1, i, j);
      const double fd_error = std::abs(b - scaled(J2, i, j));
      INFO(e_name << ' ' << p.kind << " t = " << p.t << " d f_" << i << " / d x_" << j << ": " << a
                  << " vs " << b << " (estimated error " << fd_error << ", row max " << row << ")");
      CHECK(std::abs(a - b) <= 2.0 * fd_error + rel * row + floor + 1e-300);
      // the reference's own error must stay small, or the allowance above could swallow any
      // mistake (a probe on a kink of the law): for exact Jacobians, 1e-4 of the row
      if (exact) CHECK(fd_error <= 1e-4 * row + floor + 1e-300);
    }
  }
}

}  // namespace

TEST_CASE(
    "every scene's Jacobian agrees with central differences in free flight, impact and "
    "loaded sticking contact",
    "[jacobian][stiff]") {
  for (const SceneEntry& e : scene_catalogue()) {
    const auto scene = make_scene(e.name, probe_parameters(e.name));
    // impact-pair's impact is over within its first 2 ms
    const double span = e.name == "impact-pair" ? 2e-3 : 0.3;
    std::vector<Probe> probes;
    find_free_and_sticking(*scene, span, probes);
    if (scene->contact_count() > 0) find_impact(*scene, span, probes);
    std::cout << e.name << (scene->exact_jacobian() ? ": exact Jacobian" : ": forward differences")
              << ", probes:";
    for (const Probe& p : probes) std::cout << ' ' << p.kind << " (t = " << p.t << " s)";
    std::cout << '\n';
    // every scene is probed somewhere; the rod-end scenes (exact Jacobians, the ones the
    // stiff methods are for) in all three regimes
    CHECK(!probes.empty());
    if (scene->exact_jacobian()) {
      INFO(e.name << ": a free state, an impact and a loaded sticking state under -100 N m");
      CHECK(probes.size() == 3u);
    }
    for (const Probe& p : probes) check_probe(std::string(e.name), *scene, p);
  }
}

TEST_CASE("friction.mode switch: the rod-end scenes' exact Jacobian holds a stuck contact",
          "[jacobian][stiff][friction_mode]") {
  // The stuck contact's force is solved from every other force on the spheres
  // (core/contact_stick.hpp), in the same template the dual numbers differentiate: at a loaded
  // state held stuck (the latch's default branch), the exact Jacobian must agree with central
  // differences as strictly as the law's does.
  for (const char* name : {"rod-end-kinematic", "rod-end-actuator"}) {
    ParameterSet p = probe_parameters(name);
    p.set("friction.mode", Json("switch"));
    const auto scene = make_scene(name, p);
    REQUIRE(scene->exact_jacobian());
    std::vector<Probe> probes;
    find_free_and_sticking(*scene, 0.3, probes);
    const Probe* stuck = nullptr;
    for (const Probe& q : probes)
      if (q.kind.rfind("sticking", 0) == 0) stuck = &q;
    INFO(name);
    REQUIRE(stuck != nullptr);
    REQUIRE_FALSE(stuck->d.contacts[0].slipping);
    // held within the static limit there (a force that holds it, not the limit's direction)
    CHECK(scene->stick_demand(0, stuck->t, stuck->x.data(), stuck->d) < 1.0);
    check_probe(name, *scene, *stuck);
  }
}
