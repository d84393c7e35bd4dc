# Sourced by the e2e scripts that run `iaa compare` (not a test itself: ctest runs tests/e2e/*.sh
# only). Sets `tmp` (removed on exit) and `fail`, and exits 0 with a note when this iaa was built
# without the libraries that read meshes. $1 = the script's name for messages, $2 = bin directory.
name_of_test="$1"
bin="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
probe="$("$bin/iaa" compare none.toml --mesh none.ply -o "$tmp/probe.png" 2>&1 || true)"
if grep -q "built without" <<< "$probe"; then
  echo "$name_of_test: skipped (this iaa was built without CGAL or OpenMesh)"
  exit 0
fi

# expect_no_lost_pixel LABEL SCENE MESH [compare options...]: `iaa compare` of MESH against SCENE
# loses no pixel (wherever the render certifies surface, the mesh shows some), and the render
# certifies some surface pixels, so that the check is not vacuous.
expect_no_lost_pixel() {
  local label="$1" scene="$2" mesh="$3"
  shift 3
  "$bin/iaa" compare "$scene" "$@" --mesh "$mesh" -o "$tmp/$label.png" \
    --report "$tmp/$label.json" -q > /dev/null
  grep -q '"both_surface": [1-9]' "$tmp/$label.json" || fail "$label: no surface in view"
  grep -q '"lost": 0,' "$tmp/$label.json" || {
    grep -A3 '"lost"' "$tmp/$label.json" >&2
    fail "$label: the mesh loses pixels"
  }
}
