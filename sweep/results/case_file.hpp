// The writers of a case file's parts (case_file.cpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "sweep/results.hpp"
#include "sweep/results/atomic_file.hpp"
#include "sweep/results/chunks.hpp"
#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

/// The root group's attributes; the groups /parameters and /metrics.
void write_case_root(const Context& cx, hid_t root, const CaseSpec& spec, const CaseRecord& r,
                     const Json& prov);
void write_case_parameters(const Context& cx, hid_t root, const ParameterSet& params);
void write_case_metrics(const Context& cx, hid_t root, const MetricValues& m);
/// Throws (cx.fail) when a per-case array cannot be written: a bad shape, a value not finite.
void check_case_array(const Context& cx, const CaseArray& a);
/// The per-case arrays.
void write_case_arrays(const Context& cx, hid_t root, const History& h);

}  // namespace rodend::results_detail
