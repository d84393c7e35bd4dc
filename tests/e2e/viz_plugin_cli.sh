#!/usr/bin/env bash
# The iaa command and its VTK plugin (viz/plugin_api.h, tools/iaa/viz_plugin.h):
#   - iaa itself does not link VTK (no libvtk among its NEEDED entries): commands that write no VTK
#     file start without it;
#   - without a loadable plugin (IAA_VIZ_PLUGIN naming a missing file, a library that is not the
#     plugin, or a plugin of another build) render still works, and every option that needs VTK
#     fails before the work with exit code 1, a message naming the option, the file tried and why,
#     and no output left behind;
#   - with the plugin beside iaa, the same commands write their files.
# Skipped (exit 0) when this build has no plugin (IAA_WITH_VTK=OFF; tests/e2e/disabled_cli.sh
# covers that build). $1 = bin dir, $2 = source dir.
set -uo pipefail
bin="$1"
src="$2"
if [[ ! -e "$bin/libiaa_vtk.so" ]]; then
  echo "viz_plugin_cli: no plugin in this build, skipped"
  exit 0
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail=0
scene="$src/data/scenes/teardrop.toml"
sphere=(--expr 'x^2 + y^2 + z^2 - 0.5' --bounds=-1:1,-1:1,-1:1)

if readelf -d "$bin/iaa" | grep NEEDED | grep -q libvtk; then
  echo "FAIL: iaa links VTK: $(readelf -d "$bin/iaa" | grep NEEDED | grep libvtk | head -3)"
  fail=1
fi

# expect_no_plugin PLUGIN PATTERN ARGS...: with IAA_VIZ_PLUGIN=PLUGIN, `iaa ARGS` exits 1 with
# PATTERN and the plugin's path on stderr, and leaves $tmp/out empty.
expect_no_plugin() {
  local plugin="$1" pattern="$2"
  shift 2
  rm -rf "$tmp/out" && mkdir "$tmp/out"
  IAA_VIZ_PLUGIN="$plugin" "$bin/iaa" "$@" > /dev/null 2> "$tmp/err.txt"
  local rc=$?
  if [[ $rc -ne 1 ]] || ! grep -q -- "$pattern" "$tmp/err.txt" || ! grep -q -- "$plugin" "$tmp/err.txt" ||
    [[ -n "$(ls -A "$tmp/out")" ]]; then
    echo "FAIL (rc=$rc): IAA_VIZ_PLUGIN=$plugin iaa $* -> $(cat "$tmp/err.txt") [left: $(ls -A "$tmp/out")]"
    fail=1
  fi
}
missing="$tmp/no-such-plugin.so"
expect_no_plugin "$missing" "-o needs VTK" enclose "${sphere[@]}" -d 3 -q -o "$tmp/out/e.vtu"
expect_no_plugin "$missing" "-o needs VTK" enclose "${sphere[@]}" -d 3 -q -o "$tmp/out/e.pvtu"
expect_no_plugin "$missing" "--vtk needs VTK" inspect "$scene" --pixel 60,60 --vtk "$tmp/out/i.vtm"
expect_no_plugin "$missing" "--method vtk needs VTK" mesh "$scene" --method vtk -q -o "$tmp/out/m.ply"
expect_no_plugin "$missing" "--uncertified needs VTK" mesh "$scene" -q -o "$tmp/out/m.ply" \
  --uncertified "$tmp/out/u.vtu"
# A shared library that is not the plugin.
not_plugin="$(ldd "$bin/iaa" | awk '/libz[.]so/ {print $3}')"
if [[ -n "$not_plugin" ]]; then
  expect_no_plugin "$not_plugin" "has no iaa_viz_plugin_api" enclose "${sphere[@]}" -d 3 -q \
    -o "$tmp/out/e.vtu"
fi

# A plugin of another build (tests/e2e/fake_viz_plugin.cpp: another layout fingerprint).
if [[ -e "$bin/fake/libiaa_vtk.so" ]]; then
  expect_no_plugin "$bin/fake/libiaa_vtk.so" "the types it is passed differ" enclose \
    "${sphere[@]}" -d 3 -q -o "$tmp/out/e.vtu"
else
  echo "FAIL: $bin/fake/libiaa_vtk.so was not built"
  fail=1
fi
# A bare file name is the file in the working directory, not one on the library path.
rm -rf "$tmp/out" && mkdir "$tmp/out"
(cd "$bin" && IAA_VIZ_PLUGIN=libiaa_vtk.so ./iaa enclose "${sphere[@]}" -d 3 -q \
  -o "$tmp/out/e.vtu" > /dev/null) && [[ -s "$tmp/out/e.vtu" ]] ||
  { echo "FAIL: IAA_VIZ_PLUGIN=libiaa_vtk.so in its own directory"; fail=1; }

# Render and enclose without -o never load it.
IAA_VIZ_PLUGIN="$missing" "$bin/iaa" render "$scene" --width 32 --height 32 -q -o "$tmp/r.png" ||
  { echo "FAIL: render without the plugin"; fail=1; }
IAA_VIZ_PLUGIN="$missing" "$bin/iaa" enclose "${sphere[@]}" -d 3 -q > /dev/null ||
  { echo "FAIL: enclose without -o, without the plugin"; fail=1; }

# The plugin beside iaa, and named by IAA_VIZ_PLUGIN: the files are written.
for plugin in "" "$bin/libiaa_vtk.so"; do
  rm -rf "$tmp/out" && mkdir "$tmp/out"
  (
    if [[ -n "$plugin" ]]; then export IAA_VIZ_PLUGIN="$plugin"; else unset IAA_VIZ_PLUGIN; fi
    "$bin/iaa" enclose "${sphere[@]}" -d 3 -q -o "$tmp/out/e.vtu" > /dev/null &&
      "$bin/iaa" inspect "$scene" --pixel 60,60 --vtk "$tmp/out/i.vtm" > /dev/null &&
      "$bin/iaa" mesh "$scene" --method vtk --resolution 32 -q -o "$tmp/out/m.ply" > /dev/null
  ) || { echo "FAIL: with the plugin '${plugin:-beside iaa}'"; fail=1; }
  for f in e.vtu i.vtm m.ply; do
    [[ -s "$tmp/out/$f" ]] || { echo "FAIL: with the plugin '${plugin:-beside iaa}': no $f"; fail=1; }
  done
done

[[ $fail -eq 0 ]] && echo "viz_plugin_cli: ok"
exit $fail
