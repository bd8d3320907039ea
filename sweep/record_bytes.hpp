// A case's record as bytes, for the MPI runner (sweep/mpi_runner.cpp): a worker rank sends the
// record of each case it ran to rank 0 with its next request, so that rank 0 puts it in the
// summary without reading the case file back. What is sent is what run_case returned, as the
// threads of one process put it in the summary: the results are the same whichever rank ran
// the case. Doubles are sent as their bytes (NaN metrics included); the ranks of one job run
// the same build on the same architecture.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "sweep/results.hpp"

namespace rodend {

/// Appends the record of case `slot` (its position in Study::cases) to `out`: every field of
/// sweep/case_record.def and the metrics, as the spool encodes them (encode_record). The
/// receiver takes index, scene and grid coordinates from its own copy of the case.
void pack_record(std::size_t slot, const CaseRecord& rec, std::string& out);

/// Reads one record packed by pack_record from the front of `in` and advances it. Returns the
/// slot; `rec` gets the packed fields. Throws std::runtime_error when `in` is short or
/// malformed.
std::size_t unpack_record(std::string_view& in, CaseRecord& rec);

}  // namespace rodend
