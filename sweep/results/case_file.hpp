// The writers of a case file's parts (case_file.cpp), shared with its template
// (case_from_template.cpp).
#pragma once

#include <cstddef>
#include <filesystem>
#include <vector>

#include "sweep/results.hpp"
#include "sweep/results/atomic_file.hpp"
#include "sweep/results/chunks.hpp"
#include "sweep/results/hdf5.hpp"

namespace rodend::results_detail {

/// What a case file is made of.
struct CaseParts {
  const CaseSpec& spec;
  const CaseRecord& record;
  const History& history;
  const Json& prov;
  const std::vector<EncodedSignal>& encoded;
  std::size_t estimate;  ///< of the image [bytes]
};

/// The root group's attributes; the groups /parameters and /metrics.
void write_case_root(const Context& cx, hid_t root, const CaseSpec& spec, const CaseRecord& r,
                     const Json& prov);
void write_case_parameters(const Context& cx, hid_t root, const ParameterSet& params);
void write_case_metrics(const Context& cx, hid_t root, const MetricValues& m);
/// Throws (cx.fail) when a per-case array cannot be written: a bad shape, a value not finite.
void check_case_array(const Context& cx, const CaseArray& a);
/// The per-case arrays; `raw`: where HDF5 put each one is recorded there (a template: the
/// arrays are then not kept, template_driver.hpp).
void write_case_arrays(const Context& cx, hid_t root, const History& h, CaseSlots* raw = nullptr);

/// The case file's image (without its user block) from its template (case_template.hpp),
/// building the template first if there is none for its shape, in the calling thread's
/// ScratchSlot::image. Empty: the case cannot have a template; HDF5 builds it.
ByteSpan image_from_template(const std::filesystem::path& path, const CaseParts& c);

}  // namespace rodend::results_detail
