# The teardrop's guaranteed enclosure: boxes that provably contain the whole surface, thin neck
# included, written as a .vtu of voxels (open it in ParaView, or with iaa-viz).
set -euo pipefail
echo "== iaa enclose: boxes that provably contain the teardrop (depth 7, possible boxes refined 3 levels)"
"$bin/iaa" enclose "$root/data/scenes/teardrop.toml" --depth 7 --refine-possible 3 -q \
  -o "$out/teardrop-enclosure.vtu" --report "$out/teardrop-enclosure.json"
echo "enclosure: $out/teardrop-enclosure.vtu (report: $out/teardrop-enclosure.json)"
