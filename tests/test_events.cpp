// Issue 20 item 1: contact onset is an event for every method of the menu, so that no method
// steps over an impact whatever its tolerance, step or sample interval. Every method at its
// default settings, on gravity-drop (22 bounces on a fixed socket, thesis fig. 3.24) and
// impact-pair (one free impact), for sample intervals 1e-2, 1e-3 and 1e-4 s.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "core/integrator.hpp"
#include "fixture.hpp"
#include "sweep/metrics.hpp"
#include "sweep/runner.hpp"
#include "sweep/study.hpp"

using namespace rodend;
using namespace rodend::test;

namespace {

/// One case: `method` at its default settings (IntegratorSettings) on `scene`.
CaseRecord run_default(const std::string& scene, const std::string& method, double end,
                       double sample_interval) {
  const Json doc = {{"name", "events-test"},
                    {"scene", scene},
                    {"integrator", {{"method", method}}},
                    {"time", {{"end", end}, {"sample_interval", sample_interval}}},
                    {"signals", Json::array({"penetration"})}};
  const Study s = parse_study(doc, "events-test.json", "/tmp/rodend-results");
  REQUIRE(s.cases.size() == 1);
  History h;
  return run_case(s.cases.at(0), h);
}

double metric_of(const CaseRecord& r, MetricId id) {
  return r.metrics[static_cast<std::size_t>(id)];
}

/// The matrix of one scene: every method x every sample interval is ok, counts the same
/// impacts, and the first-impact restitution agrees within 1e-3 (issue 20's bound) across the
/// intervals and across the methods.
void check_matrix(const std::string& scene, double end, int impacts) {
  std::map<std::string, double> restitution;
  double lo = INFINITY, hi = -INFINITY;
  for (std::string_view m : choice_names(IntegratorMethod{})) {
    const std::string method(m);
    double m_lo = INFINITY, m_hi = -INFINITY;
    for (double dt : {1e-2, 1e-3, 1e-4}) {
      CAPTURE(scene, method, dt);
      const CaseRecord r = run_default(scene, method, end, dt);
      INFO(r.message);
      REQUIRE(r.status == RunStatus::ok);
      CHECK(metric_of(r, MetricId::impact_count) == impacts);
      const double e = metric_of(r, MetricId::first_impact_restitution);
      m_lo = std::min(m_lo, e), m_hi = std::max(m_hi, e);
    }
    measured(scene + " " + method + ": restitution spread over sample intervals", m_hi - m_lo,
             1e-3);
    CHECK(m_hi - m_lo <= 1e-3);
    lo = std::min(lo, m_lo), hi = std::max(hi, m_hi);
  }
  measured(scene + ": restitution spread over methods and intervals", hi - lo, 1e-3);
  CHECK(hi - lo <= 1e-3);
}

}  // namespace

// measured (git i20-events): spread of first_impact_restitution over the three intervals at most
// 1.7e-4 (fehlberg78, gravity-drop), over every method and interval 8.5e-4 on gravity-drop
// (0.84476 fehlberg78 to 0.84561 rosenbrock4: the metric reads the rate at the first step end
// after the episode, so it carries each method's step there) and 3.5e-4 on impact-pair. Before:
// fehlberg78 on gravity-drop failed energy_residual_limit at 1e-2 and 1e-3 (it stepped over the
// first impact: its 7(8) error estimate has nodes at the step ends only).
TEST_CASE("events: every method at its defaults, gravity-drop, every sample interval",
          "[integrators][events]") {
  check_matrix("gravity-drop", 0.3, 22);  // 22 bounces in 0.3 s with every method
}

TEST_CASE("events: every method at its defaults, impact-pair, every sample interval",
          "[integrators][events]") {
  check_matrix("impact-pair", 1e-2, 1);  // ends before the ball reaches the opposite wall
}

TEST_CASE("events: a ball coming to rest on the wall never stalls the driver",
          "[events][integrator]") {
  // Low restitutions: the ball's last bounces graze the wall, and a located separation may not
  // be reproduced by the step re-taken up to it. The driver once re-took such an event 2.6e-15 s
  // later, again and again, until the step budget ran out (restitution 0.13594627594627595, the
  // 185th case of bench/memory.sh: 2e7 steps, 179 s). Every case here takes 400-700 steps; a
  // bound 10x above that fails a stall long before the budget (2e7) does.
  std::vector<double> restitutions{0.13594627594627595};
  for (int i = 0; i < 48; ++i) restitutions.push_back(0.1 + 0.3 * i / 47.0);
  for (const double e : restitutions) {
    const Json doc = {{"name", "events-rest"},
                      {"scene", "gravity-drop"},
                      {"parameters", {{"contact.restitution", e}}},
                      {"integrator", {{"max_steps", 7000}}},
                      {"time", {{"end", 0.05}, {"sample_interval", 1e-3}}},
                      {"signals", Json::array({"penetration"})}};
    const Study s = parse_study(doc, "events-rest.json", "/tmp/rodend-results");
    History h;
    const CaseRecord r = run_case(s.cases.at(0), h);
    CAPTURE(e, r.message, r.steps_accepted);
    REQUIRE(r.status == RunStatus::ok);
    CHECK(r.steps_accepted < 7000);
  }
}
