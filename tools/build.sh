#!/usr/bin/env bash
# Configures and builds iaa in build/ (Release, Ninja). Used by demo.sh, test.sh and soak.sh.
# IAA_TARGETS="a b" builds only those targets.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib/paths.sh"  # root, build, fuzz_build, jobs
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@"
fi
# shellcheck disable=SC2086  # IAA_TARGETS is a list of words
cmake --build "$build" -j "$jobs" ${IAA_TARGETS:+--target $IAA_TARGETS}
