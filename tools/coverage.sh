#!/usr/bin/env bash
# make coverage: line and branch coverage of what the unit and integration
# tests ran in the COV=1 build (gcovr over its .gcda files). Prints the
# core's figure (src/core, the code a board runs) and the whole tree's;
# writes BUILD/coverage.html. Figures only: nothing is asserted here.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/cov}
echo "coverage of src/core (the portable core):"
gcovr -r . --object-directory "$build/obj" --filter 'src/core/' --print-summary -s --txt "$build/coverage-core.txt" | sed 's/^/  /'
echo "coverage of everything tandem compiles (core, daemons, simulator, tools):"
gcovr -r . --object-directory "$build/obj" --filter 'src/' --filter 'sim/' --filter 'tools/' \
      --html "$build/coverage.html" --print-summary -s | tail -3 | sed 's/^/  /'
echo "details: $build/coverage.html"
