#!/usr/bin/env bash
# Sets up, builds and runs every test. Exits non-zero on any failure.
#   tools/test.sh            everything (unit, property, end-to-end, short fuzz run)
#   IAA_FUZZ_SECONDS=0 tools/test.sh   skips the fuzz run
#   IAA_CLANG=0 tools/test.sh          skips the clang build (disabled-library checks, fuzz run)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
"$root/tools/setup.sh"
"$root/tools/build.sh"
build="${IAA_BUILD_DIR:-$root/build}"
(cd "$build" && ctest --output-on-failure -j "$(nproc)" --timeout 900)

# The clang build (build-fuzz: sanitizers on, CGAL, OpenMesh and VTK off) when clang is available:
# the iaa tool, whose commands that need a left-out library must fail cleanly
# (tests/e2e/disabled_cli.sh), and a short libFuzzer run of the expression parser.
seconds="${IAA_FUZZ_SECONDS:-20}"
if [ "${IAA_CLANG:-1}" != "0" ] && command -v clang++-14 >/dev/null 2>&1; then
  fuzz_build="$root/build-fuzz"
  if [ ! -f "$fuzz_build/CMakeCache.txt" ]; then
    CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$fuzz_build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DIAA_FUZZ=ON -DIAA_WITH_CGAL=OFF -DIAA_WITH_OPENMESH=OFF -DIAA_WITH_VTK=OFF \
      -DIAA_BUILD_BENCH=OFF >/dev/null
  fi
  targets=(iaa_cli)
  if [ "$seconds" != "0" ]; then targets+=(fuzz_parser); fi
  cmake --build "$fuzz_build" -j "$(nproc)" --target "${targets[@]}"
  bash "$root/tests/e2e/disabled_cli.sh" "$fuzz_build/bin" "$root"
  if [ "$seconds" != "0" ]; then
    corpus="$(mktemp -d)"
    cp "$root"/tests/fuzz/corpus/* "$corpus"/
    echo "fuzz: running the parser fuzzer for ${seconds}s"
    "$fuzz_build/bin/fuzz_parser" -max_total_time="$seconds" -max_len=4096 -timeout=5 \
      -print_final_stats=1 "$corpus" 2>"$fuzz_build/fuzz.log" || { tail -50 "$fuzz_build/fuzz.log"; exit 1; }
    grep -E "stat::number_of_executed_units" "$fuzz_build/fuzz.log" || true
    rm -rf "$corpus"
    echo "fuzz: no crash"
  fi
fi
