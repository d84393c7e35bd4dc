#!/usr/bin/env bash
# Sets up, builds and runs every test. Exits non-zero on any failure.
#   tools/test.sh            everything (unit, property, end-to-end, short fuzz run)
#   IAA_FUZZ_SECONDS=0 tools/test.sh   skips the fuzz run
#   IAA_CLANG=0 tools/test.sh          skips the clang build (disabled-library checks, fuzz run)
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib/paths.sh"  # root, build, fuzz_build, jobs
cd "$root"
"$root/tools/setup.sh"
"$root/tools/build.sh"
(cd "$build" && ctest --output-on-failure -j "$(nproc)" --timeout 900)

# The clang build (build-fuzz: sanitizers on, CGAL, OpenMesh and VTK off; tools/build_fuzz.sh) when
# clang is available: the iaa tool, whose commands that need a left-out library must fail cleanly
# (tests/e2e/disabled_cli.sh), and short libFuzzer runs of the expression parser and of scene
# files (tools/fuzz.sh).
seconds="${IAA_FUZZ_SECONDS:-20}"
if [ "${IAA_CLANG:-1}" != "0" ] && command -v clang++-14 >/dev/null 2>&1; then
  targets=(iaa_cli)
  if [ "$seconds" != "0" ]; then targets+=(fuzz_parser fuzz_scene); fi
  "$root/tools/build_fuzz.sh" "${targets[@]}"
  bash "$root/tests/e2e/disabled_cli.sh" "$root/build-fuzz/bin" "$root"
  if [ "$seconds" != "0" ]; then
    "$root/tools/fuzz.sh" parser "$seconds"
    "$root/tools/fuzz.sh" scene "$seconds"
  fi
fi
