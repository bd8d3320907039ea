// `rodend analyze RESULTS ...` and `rodend calibrate CONFIG ...`: the sensitivity and
// uncertainty analysis of a designed study (docs/uncertainty.md) and the calibration from a
// measured record (docs/health-monitoring.md). They are Python modules' (rodend.analyze,
// rodend.calibrate, OpenTURNS); this runs them under the Python the project uses, with the
// package of this build.
#pragma once

#include <string>
#include <vector>

namespace rodend {

/// Replaces the process by `python3 -m rodend.analyze ARGS...` (python3: $RODEND_PYTHON, else
/// /usr/bin/python3; the package: PYTHONPATH gets this build's source python/ folder, and
/// RODEND_BUILD_DIR this executable's folder when unset). Returns only on failure, with 2 and a
/// message on stderr.
int exec_analyze(const std::vector<std::string>& args);

/// The same for `rodend calibrate CONFIG ...`: `python3 -m rodend.calibrate ARGS...`, the
/// calibration of unknown parameters from a measured record (docs/health-monitoring.md).
int exec_calibrate(const std::vector<std::string>& args);

}  // namespace rodend
