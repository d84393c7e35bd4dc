#!/usr/bin/env bash
# Configures (once) and builds targets of the clang build with the sanitizers, build-fuzz/:
# clang-14, AddressSanitizer + UndefinedBehaviorSanitizer + libFuzzer coverage on every target,
# CGAL, OpenMesh and VTK off. Used by tools/test.sh and tools/soak.sh.
#   tools/build_fuzz.sh TARGET...
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib/paths.sh"  # root, build, fuzz_build, jobs
if [ ! -f "$fuzz_build/CMakeCache.txt" ]; then
  CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$fuzz_build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DIAA_FUZZ=ON -DIAA_WITH_CGAL=OFF -DIAA_WITH_OPENMESH=OFF -DIAA_WITH_VTK=OFF -DIAA_WITH_MPI=OFF \
    -DIAA_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$fuzz_build" -j "$jobs" --target "$@"
