#!/usr/bin/env bash
# Sets up, builds, and runs iaa on the bundled default scene.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
"$root/tools/setup.sh"
"$root/tools/build.sh"
bin="${IAA_BUILD_DIR:-$root/build}/bin"
out="$root/out"
mkdir -p "$out"
expr='0.5*x^5 + 0.5*x^4 - y^2 - z^2'
echo "== the teardrop's expression near its thin neck"
"$bin/iaa" eval "$expr" --at -0.05,0,0 --box -0.05:0.05,-0.01:0.01,-0.01:0.01
