// `rodend analyze RESULTS ...`: the sensitivity and uncertainty analysis of a designed study
// (docs/uncertainty.md). It is the Python module's (rodend.analyze, OpenTURNS); this runs it
// under the Python the project uses, with the package of this build.
#pragma once

#include <string>
#include <vector>

namespace rodend {

/// Replaces the process by `python3 -m rodend.analyze ARGS...` (python3: $RODEND_PYTHON, else
/// /usr/bin/python3; the package: PYTHONPATH gets this build's source python/ folder, and
/// RODEND_BUILD_DIR this executable's folder when unset). Returns only on failure, with 2 and a
/// message on stderr.
int exec_analyze(const std::vector<std::string>& args);

}  // namespace rodend
