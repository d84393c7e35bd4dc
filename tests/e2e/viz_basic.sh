#!/usr/bin/env bash
# iaa-viz end to end: headless render (own Xvfb with DISPLAY unset) of an enclosure and of a mesh
# (`iaa-viz enclose`, `iaa-viz mesh`), PNGs that are not blank; clear errors for a missing file, an
# unknown type, a bad size. Colours, cameras and display errors: tests/e2e/viz_cli_test.cpp.
set -euo pipefail
bin="$1"
src="${2:-.}"
[ -x "$bin/iaa-viz" ] || { echo "iaa-viz not built: skipped"; exit 0; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
unset DISPLAY
cat > "$tmp/s.toml" <<'TOML'
name = "sphere"
[surface]
expression = "x^2 + y^2 + z^2 - 0.5"
min = [-1, -1, -1]
max = [1, 1, 1]
[camera]
eye = [0, 0, 3]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 40
TOML
"$bin/iaa-viz" enclose "$tmp/s.toml" --depth 4 -q --size 200x150 -o "$tmp/enc.png"
test -s "$tmp/enc.png"
# Not blank: the PNG of a white picture at this size compresses to far less.
[ "$(stat -c %s "$tmp/enc.png")" -gt 3000 ] || { echo "enc.png looks blank"; exit 1; }
# The mesh shortcut: the certified mesh beside the enclosure (colours: tests/e2e/viz_cli_test.cpp).
"$bin/iaa-viz" mesh "$tmp/s.toml" --depth 4 --resolution 32 -q --size 300x150 -o "$tmp/mesh.png" >"$tmp/out"
grep -q "^mesh: certified, .* triangles" "$tmp/out" || { echo "mesh: no summary line"; cat "$tmp/out"; exit 1; }
grep -q "(300x150, " "$tmp/out" || { echo "mesh: wrong size"; cat "$tmp/out"; exit 1; }
[ "$(stat -c %s "$tmp/mesh.png")" -gt 3000 ] || { echo "mesh.png looks blank"; exit 1; }
# A certified mesh written as binary STL, with the boxes of its uncertified cells (the teardrop's
# singular point) over it.
td="$src/data/scenes/teardrop.toml"
if "$bin/iaa" mesh "$td" --resolution 32 --binary -o "$tmp/s.stl" --uncertified "$tmp/unc.vtu" \
    -q >/dev/null 2>"$tmp/err"; then
  "$bin/iaa-viz" "$tmp/s.stl" "$tmp/unc.vtu" --scene "$td" --size 200x150 -o "$tmp/stl.png" >"$tmp/out"
  grep -q "(200x150, 2 layers)" "$tmp/out" || { echo "stl: wrong summary"; cat "$tmp/out"; exit 1; }
  [ "$(stat -c %s "$tmp/stl.png")" -gt 3000 ] || { echo "stl.png looks blank"; exit 1; }
elif ! grep -q "built without" "$tmp/err"; then
  cat "$tmp/err"; exit 1
fi
if "$bin/iaa-viz" "$tmp/missing.vtu" -o "$tmp/x.png" 2>"$tmp/err"; then echo "missing file accepted"; exit 1; fi
grep -q "no such file" "$tmp/err"
touch "$tmp/a.xyz"
if "$bin/iaa-viz" "$tmp/a.xyz" -o "$tmp/x.png" 2>"$tmp/err"; then echo "unknown type accepted"; exit 1; fi
grep -q "unknown file type" "$tmp/err"
if "$bin/iaa-viz" enclose "$tmp/s.toml" --size 5x5 -o "$tmp/x.png" 2>"$tmp/err"; then echo "bad size accepted"; exit 1; fi
grep -q "16..8192" "$tmp/err"
test ! -e "$tmp/x.png"
echo "viz_basic: ok"
