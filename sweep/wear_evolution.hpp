// The wear evolution of a case (study key "wear_evolution"): duty cycles run on
// surfaces worn by the cycles before, each update scaling one cycle's wear up to many.
#pragma once

#include "sweep/results.hpp"
#include "sweep/study.hpp"

namespace rodend {

/// Runs a case of a study with a wear_evolution section (see WearEvolutionSettings): the first
/// duty cycle's histories and metrics, the evolution's histories (group "evolution"), the
/// final worn maps and the evolution metrics.
CaseRecord run_wear_evolution(const CaseSpec& spec, History& history);

}  // namespace rodend
