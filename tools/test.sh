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

# The clang build (build-fuzz: sanitizers on, CGAL, OpenMesh, VTK and MPI off; tools/build_fuzz.sh) when
# clang is available: the unit suites under AddressSanitizer (with its leak check) and
# UndefinedBehaviorSanitizer; the iaa tool, whose commands that need a left-out library must fail
# cleanly (tests/e2e/disabled_cli.sh); and short libFuzzer runs of the expression parser and of
# scene files (tools/fuzz.sh).
seconds="${IAA_FUZZ_SECONDS:-20}"
if [ "${IAA_CLANG:-1}" != "0" ] && command -v clang++-14 >/dev/null 2>&1; then
  # The suites of core, expr, render, enclose, compare and mesh (mesh: what needs neither CGAL nor
  # OpenMesh); viz's need VTK, which this build leaves out. Any sanitizer report fails its test.
  suites=(core expr render enclose compare mesh)
  targets=(iaa_cli)
  for suite in "${suites[@]}"; do targets+=("iaa_${suite}_tests"); done
  if [ "$seconds" != "0" ]; then targets+=(fuzz_parser fuzz_scene); fi
  "$root/tools/build_fuzz.sh" "${targets[@]}"
  labels="^($(IFS='|'; echo "${suites[*]}"))\$"
  (cd "$fuzz_build" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
    ctest --output-on-failure -j "$jobs" --timeout 900 -L "$labels")
  bash "$root/tests/e2e/disabled_cli.sh" "$fuzz_build/bin" "$root"
  if [ "$seconds" != "0" ]; then
    "$root/tools/fuzz.sh" parser "$seconds"
    "$root/tools/fuzz.sh" scene "$seconds"
  fi
fi
