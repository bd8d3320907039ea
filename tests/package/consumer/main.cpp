// Runs one gravity-drop case through the installed rodend libraries and checks the free fall
// before the first contact against the analytic solution: a ball released at rest from the
// socket centre meets the wall after falling the clearance c, at t = sqrt(2 c / g) with speed
// sqrt(2 g c). Exit 0 when both agree to 1e-6 (the onset is located on the dense output to
// round-off; measured difference below 1e-9), 1 otherwise.
#include <cmath>
#include <cstdio>
#include <string>

#include <rodend/sweep/runner.hpp>
#include <rodend/sweep/study.hpp>

int main() {
  using namespace rodend;
  const double c = 5e-4, g = 9.81;
  const Json doc = {{"scene", "gravity-drop"},
                    {"parameters", {{"contact.clearance", c}}},
                    {"integrator", {{"method", "dopri5"}, {"abs_tol", 1e-9}, {"rel_tol", 1e-9}}},
                    {"time", {{"end", 0.03}, {"sample_interval", 1e-3}}}};
  const Study study = parse_study(doc, "consumer.json");
  History history;
  const CaseRecord r = run_case(study.cases.at(0), history);
  const double t = r.metrics[static_cast<std::size_t>(MetricId::first_contact_time)];
  const double v = r.metrics[static_cast<std::size_t>(MetricId::first_impact_speed)];
  const double t_exact = std::sqrt(2 * c / g), v_exact = std::sqrt(2 * g * c);
  std::printf(
      "status %s, %lld samples, first contact %.12g s (exact %.12g), speed %.12g m/s "
      "(exact %.12g)\n",
      std::string(to_string(r.status)).c_str(), history.samples, t, t_exact, v, v_exact);
  const bool ok = r.status == RunStatus::ok && std::abs(t / t_exact - 1) < 1e-6 &&
                  std::abs(v / v_exact - 1) < 1e-6 && history.samples == 31;
  return ok ? 0 : 1;
}
