#!/usr/bin/env bash
# End-to-end: `iaa compare` of a sphere mesh against the sphere scene, and its errors for
# unreadable, empty and NaN meshes. $1 = bin directory, $2 = source directory.
set -euo pipefail
# shellcheck source=lib/compare.bash
source "$(dirname "${BASH_SOURCE[0]}")/lib/compare.bash" mesh_compare "$1"
cat > "$tmp/sphere.toml" <<'TOML'
name = "sphere"
[surface]
expression = "x^2 + y^2 + z^2 - 0.64"
min = [-1, -1, -1]
max = [1, 1, 1]
[camera]
eye = [0.4, 0.5, 3.0]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 40
[image]
width = 64
height = 64
TOML

"$bin/iaa" mesh "$tmp/sphere.toml" --resolution 64 -o "$tmp/s.ply" -q > /dev/null
"$bin/iaa" compare "$tmp/sphere.toml" --mesh "$tmp/s.ply" -o "$tmp/d.png" --report "$tmp/d.json" -q > "$tmp/out.txt"
[ -s "$tmp/d.png" ] || fail "no diff picture"
grep -q '"wrong": 0' "$tmp/d.json" || { cat "$tmp/d.json"; fail "wrong pixels for the sphere's own mesh"; }
grep -q '^lost' "$tmp/out.txt" || fail "summary"

expect_error() {  # expect_error PATTERN -- command...
  local pattern="$1"
  shift
  if "$@" > "$tmp/stdout" 2> "$tmp/stderr"; then fail "should fail: $*"; fi
  grep -q -- "$pattern" "$tmp/stderr" || { cat "$tmp/stderr"; fail "message '$pattern' for: $*"; }
  [ ! -e "$tmp/e.png" ] || fail "partial output left behind"
}
echo "not a mesh" > "$tmp/bad.ply"
printf 'OFF\n0 0 0\n' > "$tmp/empty.off"
# A binary PLY with a NaN coordinate (float 0x7fc00000); zero is 00000000, one is 0000803f.
{
  printf 'ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n'
  printf 'property float y\nproperty float z\nelement face 1\n'
  printf 'property list uchar int vertex_indices\nend_header\n'
  printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00\x00'
  printf '\x00\x00\x80\x3f\x00\x00\x00\x00\x00\x00\x00\x00'
  printf '\x00\x00\xc0\x7f\x00\x00\x80\x3f\x00\x00\x00\x00'
  printf '\x03\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00'
} > "$tmp/nan.ply"
expect_error "bad.ply" "$bin/iaa" compare "$tmp/sphere.toml" --mesh "$tmp/bad.ply" -o "$tmp/e.png"
expect_error "no triangles" "$bin/iaa" compare "$tmp/sphere.toml" --mesh "$tmp/empty.off" -o "$tmp/e.png"
expect_error "non-finite" "$bin/iaa" compare "$tmp/sphere.toml" --mesh "$tmp/nan.ply" -o "$tmp/e.png"
expect_error "missing.ply" "$bin/iaa" compare "$tmp/sphere.toml" --mesh "$tmp/missing.ply" -o "$tmp/e.png"
expect_error ".png" "$bin/iaa" compare "$tmp/sphere.toml" --mesh "$tmp/s.ply" -o "$tmp/e.jpg"
echo "mesh_compare: ok"
