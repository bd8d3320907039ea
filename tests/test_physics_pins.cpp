// Issue 37 item 7: tests that pin what, before them, only the stored regression references
// caught (or nothing caught): one-line mutations of the physics must fail a test that needs no
// stored reference. Each test names the mutation it was proved against and what it did then.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "fixture.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

/// Prothero-Robinson, as in test_stiff.cpp, started at a phase phi of its solution:
/// x' = -lambda (x - sin(t + phi)) + cos(t + phi), x(0) = sin(phi), exact x = sin(t + phi),
/// lambda = 1e4 s^-1. From the exact x(0) the error after the first accepted step is that step's
/// local error, nothing propagated; the phase moves where along the solution the step is taken.
class ProtheroRobinson final : public Scene {
 public:
  static constexpr double lambda = 1e4;  // [1/s]
  explicit ProtheroRobinson(double phi) : phi_(phi) {}
  double exact(double t) const { return std::sin(t + phi_); }
  std::string_view name() const override { return "prothero-robinson"; }
  Features features() const override { return {}; }
  int state_size() const override { return 1; }
  void initial_state(double* x) const override { x[0] = exact(0.0); }
  void state_scale(double* s) const override { s[0] = 1.0; }
  void derivatives(double t, const double* x, const DiscreteState&, double* dx) const override {
    dx[0] = -lambda * (x[0] - exact(t)) + std::cos(t + phi_);
  }
  std::span<const SignalId> signals() const override { return kSignals; }
  void outputs(double, const double* x, const DiscreteState&, SignalFrame& f) const override {
    f.set(SignalId::eccentricity, x[0]);
  }
  EnergyTerms energy(double, const double*, const DiscreteState&) const override { return {}; }

 private:
  static constexpr std::array<SignalId, 2> kSignals{SignalId::time, SignalId::eccentricity};
  double phi_;
};

/// The first accepted step of `method` on Prothero-Robinson at phase phi, tolerances tol, the
/// first trial step the whole run (end = 2 s): its local error relative to the tolerance it
/// was accepted against, abs + rel |x| (the error checkers' weight), and the run's rejections.
struct FirstStep {
  double error_over_tol = NAN;
  double t1 = NAN;
  long long rejected = 0;
};
FirstStep oversized_first_step(const std::string& method, double tol, double phi) {
  const ProtheroRobinson scene(phi);
  const double end = 2.0;
  IntegratorSettings s;
  s.method = method;
  s.abs_tol = s.rel_tol = tol;
  s.step = end;  // the first trial step: deliberately the whole run
  s.max_step = end;
  Recorder rec({SignalId::eccentricity}, true);
  // one sample interval over the whole run: the methods without dense output step to it
  const RunResult r = simulate(scene, s, TimeSettings{end, end}, rec);
  INFO(r.message);
  REQUIRE(r.status == RunStatus::ok);
  REQUIRE(!rec.steps.empty());
  FirstStep f;
  f.t1 = rec.steps.time(0);
  const double x1 = rec.steps.get(0, SignalId::eccentricity);
  f.error_over_tol = std::abs(x1 - scene.exact(f.t1)) / (tol + tol * std::abs(x1));
  f.rejected = r.stats.steps_rejected;
  return f;
}

}  // namespace

// --- 1. step-size control: an oversized first step is rejected ---------------------------------

// Mutation: rosenbrock4 accepts a step when its error norm is <= 100 instead of <= 1
// (core/steppers_odeint.cpp, `if (e <= 1.0)` -> `if (e <= 100.0)`). Seen then: at tol 1e-6 the
// 2 s first trial step is accepted at once (0 rejections) with a local error of 9-20 x tol (the
// three phases); at tol 1e-8 the first accepted steps carry 6.9-72 x tol; 9 checks fail. Without
// the mutation: <= 1.44 x tol. Before this test nothing failed on it (test_stiff.cpp asks only
// for a global error < 10 x tol at the end).
TEST_CASE("pins: every adaptive method rejects an oversized first step on a stiff problem",
          "[pins][stiff]") {
  // bulirsch_stoer is left out: odeint runs its step-size control, so its rejections are not
  // counted, and its first accepted step's error is not bounded by its tolerance on this problem
  // (the [!shouldfail] test below)
  const std::string method = GENERATE(as<std::string>{}, "dopri5", "cash_karp54", "fehlberg78",
                                      "rosenbrock4", "cvode_bdf", "cvode_adams");
  for (const double tol : {1e-6, 1e-8})
    for (const double phi : {0.0, 1.0, 2.0}) {
      const FirstStep f = oversized_first_step(method, tol, phi);
      CAPTURE(method, tol, phi, f.t1, f.rejected, f.error_over_tol);
      // a 2 s step across a 1e4 s^-1 eigenvalue is far outside every method's accuracy (the
      // explicit ones' stability too): the controller must reject it at least once
      CHECK(f.rejected > 0);
      // and the step it accepts has a local error of the order of the tolerance: its error
      // estimate (of the embedded lower-order solution, which is not the one kept) passed <= 1,
      // which bounds the kept solution's error only up to the estimate's own error. measured
      // max over tol and phase: dopri5 0.44, cash_karp54 1.19, fehlberg78 0.26, rosenbrock4
      // 1.44, cvode_bdf 0.32, cvode_adams 0.029 (x tol). The bound 3 is 2x the worst and 2.3x
      // below the smallest error a controller accepting 100 x tol let through (6.9 x tol)
      measured("oversized first step: local error / tol, " + method, f.error_over_tol, 3.0);
      CHECK(f.error_over_tol <= 3.0);
    }
}

// A known defect, not a pin: bulirsch_stoer (odeint's bulirsch_stoer_dense_out, which runs its
// own step-size control) accepts first steps whose local error is far above its tolerance on
// this stiff problem: measured 12.4 x tol (and over a 2 s run at tol 1e-6, global errors up to
// 1.1e4 x tol, where the other methods stay within 14 x tol). The extrapolation's error
// estimate of the explicit modified midpoint rule is not to be trusted at h lambda >> 1. Marked
// [!shouldfail]: it passes while the defect is there and fails once it is gone (then drop the
// tag and add the method to the test above).
TEST_CASE("pins: bulirsch_stoer's first step on a stiff problem", "[pins][stiff][!shouldfail]") {
  double worst = 0.0;
  for (const double tol : {1e-6, 1e-8})
    for (const double phi : {0.0, 1.0, 2.0})
      worst = std::max(worst, oversized_first_step("bulirsch_stoer", tol, phi).error_over_tol);
  measured("oversized first step: local error / tol, bulirsch_stoer", worst, 3.0);
  CHECK(worst <= 3.0);
}
