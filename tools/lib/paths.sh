# Sourced by the tools/*.sh scripts (not run): where the repository and its build trees are, so that
# every script reads the same environment variables the same way.
#   root        the repository (this file is tools/lib/paths.sh)
#   build       the Release build: IAA_BUILD_DIR, default build/
#   fuzz_build  the clang build with the sanitizers: IAA_FUZZ_BUILD_DIR, default build-fuzz/
#   jobs        parallel build jobs: IAA_JOBS, default the number of cores
# shellcheck shell=bash disable=SC2034  # the variables are for the sourcing script
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${IAA_BUILD_DIR:-$root/build}"
fuzz_build="${IAA_FUZZ_BUILD_DIR:-$root/build-fuzz}"
jobs="${IAA_JOBS:-$(nproc)}"
