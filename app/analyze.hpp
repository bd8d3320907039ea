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
/// /usr/bin/python3). The package rodend: the one that Python imports by itself (PYTHONPATH,
/// `pip install`), else PREFIX/share/rodend/python beside an installed executable, else the
/// source tree's python/ folder named by the file rodend-python-path that the configure step
/// writes beside the executable of a build tree; RODEND_BUILD_DIR gets this executable's folder
/// when unset. Returns only on failure, with 2 and a message on stderr naming where it looked.
int exec_analyze(const std::vector<std::string>& args);

/// The same for `rodend calibrate CONFIG ...`: `python3 -m rodend.calibrate ARGS...`, the
/// calibration of unknown parameters from a measured record (docs/health-monitoring.md).
int exec_calibrate(const std::vector<std::string>& args);

}  // namespace rodend
