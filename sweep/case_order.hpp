// The order in which a run takes its cases: the most expensive first, where a cheap prediction
// of a case's cost exists, so that no long case is left to start last while the other threads
// idle (longest-processing-time-first list scheduling). Only the order changes: every case, its
// id, its file and its row in the summary are those of the grid order.
#pragma once

#include <cstddef>
#include <vector>

#include "core/params.hpp"
#include "sweep/study.hpp"

namespace rodend {

/// A cheap prediction of a case's cost from its parameters, in no unit: only its order among
/// the cases of one study means something, and 0 means "no prediction". Today the magnitude of
/// a sustained hinge moment (kind constant: |constant_moment| [N m]): under it the ball sticks
/// and slips at the thesis friction law's Stribeck drop and a case costs 3-8 times an unloaded
/// one (docs/performance.md "Largest-first scheduling").
double predicted_cost(const ParameterSet& parameters);

/// Reorders `todo` (indices into study.cases) by predicted_cost, the largest first; stable, so
/// cases of equal prediction keep their grid order, and a study without a prediction runs in
/// grid order.
void order_largest_first(const Study& study, std::vector<std::size_t>& todo);

}  // namespace rodend
