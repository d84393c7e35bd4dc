#!/usr/bin/env bash
# Sets up, builds, and runs iaa on the bundled default scene (data/scenes/teardrop.toml).
# Each part of the demo is a script in tools/demo.d/, run in order with $bin, $out and $root set.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
"$root/tools/setup.sh"
"$root/tools/build.sh"
bin="${IAA_BUILD_DIR:-$root/build}/bin"
out="${IAA_DEMO_OUT:-$root/out}"
mkdir -p "$out"
export root bin out
for part in "$root"/tools/demo.d/*.sh; do
  bash "$part"
done
echo
echo "demo: all outputs are in $out"
