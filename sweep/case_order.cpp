#include "sweep/case_order.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/scenes/drivers.hpp"

namespace rodend {

double predicted_cost(const ParameterSet& p) {
  if (!p.has("hinge.kind") || !p.has("hinge.constant_moment")) return 0.0;
  if (choice_from_name<HingeMomentKind>(p.text("hinge.kind")) != HingeMomentKind::constant)
    return 0.0;
  return std::abs(p.number("hinge.constant_moment"));
}

void order_largest_first(const Study& study, std::vector<std::size_t>& todo) {
  // only a hinge moment that varies between the cases can change the order, and what varies is
  // a coordinate of every case: without one, no case is resolved again (a large grid resolves
  // each case on demand)
  if (todo.empty()) return;
  const Json coordinates = study.cases[todo.front()].coordinates;
  if (!coordinates.contains("parameters.hinge.constant_moment") &&
      !coordinates.contains("parameters.hinge.kind"))
    return;
  std::vector<std::pair<double, std::size_t>> keyed;
  keyed.reserve(todo.size());
  bool any = false;
  for (const std::size_t i : todo) {
    const double cost = predicted_cost(study.cases[i].parameters);
    any = any || cost > 0.0;
    keyed.emplace_back(cost, i);
  }
  if (!any) return;
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t k = 0; k < todo.size(); ++k) todo[k] = keyed[k].second;
}

}  // namespace rodend
