// The implicit methods' ingredients: rosenbrock4's step-size control on a stiff problem with a
// known solution, and every scene's Jacobian (Scene::jacobian) against central differences.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "fixture.hpp"

using namespace rodend;

namespace {

/// Prothero-Robinson: x' = -lambda (x - sin t) + cos t, x(0) = 0, exact x = sin t. Stiff
/// (lambda = 1e4 s^-1) and non-autonomous: a method that mishandles df/dt, as odeint 1.74's
/// rosenbrock4 did (the sign of d4), is first order on it, and its steps stay tiny.
class ProtheroRobinson final : public Scene {
 public:
  static constexpr double lambda = 1e4;  // [1/s]
  std::string_view name() const override { return "prothero-robinson"; }
  Features features() const override { return {}; }
  int state_size() const override { return 1; }
  void initial_state(double* x) const override { x[0] = 0.0; }
  void state_scale(double* s) const override { s[0] = 1.0; }
  void derivatives(double t, const double* x, const DiscreteState&, double* dx) const override {
    dx[0] = -lambda * (x[0] - std::sin(t)) + std::cos(t);
  }
  std::span<const SignalId> signals() const override { return kSignals; }
  void outputs(double, const double* x, const DiscreteState&, SignalFrame& f) const override {
    f.set(SignalId::eccentricity, x[0]);
  }
  EnergyTerms energy(double, const double*, const DiscreteState&) const override { return {}; }

 private:
  static constexpr std::array<SignalId, 2> kSignals{SignalId::time, SignalId::eccentricity};
};

}  // namespace

TEST_CASE("rosenbrock4: steps grow on a stiff problem and the error follows the tolerance",
          "[rosenbrock4][stiff]") {
  const ProtheroRobinson scene;
  const double end = 2.0;
  double previous_error = INFINITY;
  for (const double tol : {1e-4, 1e-6, 1e-8}) {
    IntegratorSettings s;
    s.method = IntegratorMethod::rosenbrock4;
    s.abs_tol = s.rel_tol = tol;
    s.max_step = 1.0;
    RunObserver none;
    const RunResult r = simulate(scene, s, TimeSettings{end, end}, none);
    REQUIRE(r.status == RunStatus::ok);
    const double error = std::abs(r.final_state[0] - std::sin(end));
    const long long steps = r.stats.steps_accepted;
    INFO("tol " << tol << ": " << steps << " steps, " << r.stats.steps_rejected
                << " rejected, error " << error);
    // An L-stable order-4 method follows the smooth solution with steps set by accuracy, not by
    // the eigenvalue 1e4: an explicit method needs h < ~3/lambda, i.e. > 6,600 steps on 2 s.
    // Measured at 1e-6 and 1e-8: 15 and 696 steps (6 and 10 rejected); before the fix of d4
    // (core/steppers_odeint.cpp) the step stayed near 1e-5 s, ~2e5 steps.
    CHECK(steps < 2000);
    // the error at the end is of the order of the tolerance (measured: 1.3e-7 at 1e-6, 1.9e-10
    // at 1e-8) ...
    CHECK(error < 10 * tol);
    // ... and shrinks as it tightens
    CHECK(error < previous_error);
    previous_error = error;
  }
}

TEST_CASE("every scene's Jacobian agrees with central differences, free and in contact",
          "[jacobian][stiff]") {
  for (const SceneEntry& e : scene_catalogue()) {
    const auto scene = make_scene(e.name, ParameterSet::defaults_for(e.name));
    const int n = scene->state_size();
    const auto un = static_cast<std::size_t>(n);
    std::vector<double> scale(un);
    scene->state_scale(scale.data());
    // states: the initial one and the ends of short runs, up to three of them free and three
    // in contact (impact-pair's impact is over within its first 2 ms)
    std::vector<std::pair<double, std::vector<double>>> states;
    std::vector<double> x0(un);
    scene->initial_state(x0.data());
    states.emplace_back(0.0, x0);
    const double span = e.name == "impact-pair" ? 2e-3 : 0.3;
    int free_states = 0, contact_states = 0;
    for (int k = 1; k <= 32; ++k) {
      const double end = span * k / 32.0;
      IntegratorSettings s;
      s.method = IntegratorMethod::dopri5;
      s.abs_tol = s.rel_tol = 1e-8;
      RunObserver none;
      const RunResult r = simulate(*scene, s, TimeSettings{end, end}, none);
      REQUIRE(r.status == RunStatus::ok);
      const bool touching = scene->contact_count() > 0 &&
                            scene->contact_gap(0, r.final_state.data()).penetration > 0.0;
      int& count = touching ? contact_states : free_states;
      if (count < 3) {
        ++count;
        states.emplace_back(end, r.final_state);
      }
    }
    bool contact_seen = scene->contact_count() == 0;
    for (const auto& [t, x] : states) {
      DiscreteState d;
      bool at_kink = false;
      d.contacts.resize(static_cast<std::size_t>(scene->contact_count()));
      for (int c = 0; c < scene->contact_count(); ++c) {
        const ContactGap g = scene->contact_gap(c, x.data());
        auto& l = d.contacts[static_cast<std::size_t>(c)];
        l.in_contact = g.penetration > 0.0;
        // the contact law has a kink at delta = 0: no difference quotient holds across it
        if (std::abs(g.penetration) < 1e-6 * scene->contact_clearance(c)) at_kink = true;
        l.impact_speed = l.in_contact ? std::max(std::abs(g.penetration_rate), 1e-3) : 0.0;
        contact_seen = contact_seen || l.in_contact;
      }
      if (at_kink) continue;
      std::vector<double> J(un * un), Jc(un * un), xp = x, fp(un), fm(un), f0(un);
      scene->derivatives(t, x.data(), d, f0.data());
      scene->jacobian(t, x.data(), d, J.data());
      // reference: central differences with an increment 1e-7 of each state's scale (|x_j|
      // when larger): truncation O(h^2 f''') and round-off O(eps |f| / h) are both far below
      // the tolerance below (the Hertz law's curvature at the smallest penetrations seen,
      // ~1e-8 m, against h = 5e-11 m: (h / delta)^2 ~ 3e-5)
      for (std::size_t j = 0; j < un; ++j) {
        const double h = 1e-7 * std::max(std::abs(x[j]), scale[j]);
        xp[j] = x[j] + h;
        scene->derivatives(t, xp.data(), d, fp.data());
        xp[j] = x[j] - h;
        scene->derivatives(t, xp.data(), d, fm.data());
        xp[j] = x[j];
        for (std::size_t i = 0; i < un; ++i) Jc[i * un + j] = (fp[i] - fm[i]) / (2 * h);
      }
      // compare in scaled variables (z = x / scale: every entry in 1/s), each row against its
      // largest entry: 1e-3 of it allows the two difference quotients' errors and catches any
      // wrong term of an analytic Jacobian (an error of order one); plus the round-off of the
      // quotients, eps |f_i| / h with h ~ 1e-8 of the scale: 1e-6 |f_i / scale_i|, and 1e-9 of
      // the matrix's largest entry (terms of that size that cancel in a row, e.g. an energy
      // integral's pressure-times-flow terms)
      double largest = 0.0;
      for (std::size_t i = 0; i < un; ++i)
        for (std::size_t j = 0; j < un; ++j)
          largest = std::max(largest, std::abs(Jc[i * un + j]) * scale[j] / scale[i]);
      for (std::size_t i = 0; i < un; ++i) {
        const double floor = 1e-6 * std::abs(f0[i] / scale[i]) + 1e-9 * largest;
        double row = 0.0;
        for (std::size_t j = 0; j < un; ++j)
          row = std::max(row, std::abs(Jc[i * un + j]) * scale[j] / scale[i]);
        for (std::size_t j = 0; j < un; ++j) {
          const double a = J[i * un + j] * scale[j] / scale[i];
          const double b = Jc[i * un + j] * scale[j] / scale[i];
          INFO(e.name << " t = " << t << " d f_" << i << " / d x_" << j << ": " << a << " vs " << b
                      << " (row max " << row << ")");
          CHECK(std::abs(a - b) <= 1e-3 * row + floor + 1e-300);
        }
      }
    }
    INFO(e.name << ": a state in contact among those checked");
    CHECK(contact_seen);
  }
}
