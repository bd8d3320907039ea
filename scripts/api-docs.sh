#!/usr/bin/env bash
# The C++ API reference (docs/api/Doxyfile): HTML from the headers' comments and
# docs/api/mainpage.md, into $RODEND_API_OUT (default build/api), html/index.html first.
# Needs Debian's doxygen (apt-get install doxygen); nothing else of rodend needs it.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v doxygen >/dev/null; then
  echo "api-docs: doxygen not found (Debian: apt-get install doxygen)" >&2
  exit 2
fi
export RODEND_API_OUT="${RODEND_API_OUT:-build/api}"
mkdir -p "$RODEND_API_OUT"
doxygen docs/api/Doxyfile
echo "api-docs: $RODEND_API_OUT/html/index.html ($(grep -c . "$RODEND_API_OUT/warnings.log" || true) warning line(s) in $RODEND_API_OUT/warnings.log)" >&2
