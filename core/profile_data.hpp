// The data of a profile: one column of a data file against its time column (a recorded
// flight, a rig sequence), read once per study (sweep/profile.hpp) and attached to the
// parameter leaf that names the file (ParameterSet::attach). How a scene reads it between and
// past its samples is core/scenes/profile.hpp.
#pragma once

#include <string>
#include <vector>

namespace rodend {

/// One column of a data file against its time column: immutable once read, shared by cases.
struct ProfileData {
  std::string file;           ///< the path as the study names it
  std::string resolved;       ///< the path it was read from (against the study file's folder)
  std::string content_hash;   ///< FNV-1a 64 of the file's bytes, 16 hex digits
  std::string column;         ///< the value column (CSV header name; HDF5 dataset path)
  std::string unit;           ///< the value column's unit, as the file states it
  std::vector<double> time;   ///< strictly increasing [s]
  std::vector<double> value;  ///< [unit]
  std::vector<double> slope;  ///< pchip slopes d(value)/dt at the samples [unit/s]

  double start() const { return time.front(); }
  double end() const { return time.back(); }
};

}  // namespace rodend
