#!/usr/bin/env bash
# The installed iaa, from a built tree (ctest `install`, run by tools/test.sh):
#   1. `cmake --install` into a temporary prefix holds the commands, headers, libraries, the CMake
#      package, the scenes and the Python package;
#   2. a consumer project (tests/install/consumer) configures with find_package(iaa) against that
#      prefix, builds, and runs on a bundled scene;
#   3. the installed Python package imports and renders outside the build tree;
#   4. `cpack -G DEB` makes a package whose files (unpacked with dpkg -x, not installed: the test
#      changes nothing on the machine) include an iaa that renders the demo scene (the teardrop)
#      to the same bytes as the build's iaa.
# Where VTK is built, the installed and the packaged iaa each find their VTK plugin
# (lib*/iaa/libiaa_vtk.so, viz/plugin_api.h) and write an enclosure .vtu with it, and the package
# depends on VTK's libraries through it.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build="$(cd "$1" && pwd)"
src="$(cd "$2" && pwd)"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
fail() { echo "FAIL: $*"; exit 1; }

# 1. The prefix.
cmake --install "$build" --prefix "$prefix" >"$tmp/install.log" ||
  { cat "$tmp/install.log"; fail "cmake --install"; }
viz=""
if [ -x "$build/bin/iaa-viz" ]; then viz=bin/iaa-viz; fi
for f in bin/iaa $viz include/iaa/core/interval.h include/iaa/app/scene_loading.h \
         lib/libiaa_core.a lib/libiaa_app.a lib/cmake/iaa/iaaConfig.cmake \
         lib/cmake/iaa/iaaConfigVersion.cmake lib/cmake/iaa/iaaTargets.cmake \
         share/iaa/scenes/teardrop.toml; do
  [ -e "$prefix/$f" ] || fail "the prefix lacks $f"
done
echo "install: $(find "$prefix" -type f | wc -l) files under the prefix"
# The VTK plugin, found relative to the installed command (IAA_VIZ_PLUGIN unset).
vtu_check() {  # vtu_check IAA: writes an enclosure .vtu through the plugin
  (unset IAA_VIZ_PLUGIN; "$1" enclose --expr 'x^2 + y^2 + z^2 - 1' --bounds=-2:2,-2:2,-2:2 \
    --depth 3 -o "$tmp/plugin.vtu" >/dev/null) && [ -s "$tmp/plugin.vtu" ] && rm "$tmp/plugin.vtu"
}
if [ -e "$build/bin/libiaa_vtk.so" ]; then
  ls "$prefix"/lib*/iaa/libiaa_vtk.so >/dev/null 2>&1 || fail "the prefix lacks lib*/iaa/libiaa_vtk.so"
  vtu_check "$prefix/bin/iaa" || fail "the installed iaa does not write a .vtu through its plugin"
  echo "install: the installed iaa writes .vtu files through $(cd "$prefix" && ls lib*/iaa/libiaa_vtk.so)"
fi

# 2. A consumer project against it.
log="$tmp/consumer.log"
cmake -S "$src/tests/install/consumer" -B "$tmp/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$log" 2>&1 || { cat "$log"; fail "consumer: configure"; }
cmake --build "$tmp/consumer" >>"$log" 2>&1 || { cat "$log"; fail "consumer: build"; }
"$tmp/consumer/consumer" "$prefix/share/iaa/scenes/teardrop.toml" || fail "consumer: run"

# 3. The Python package, when it was built.
if [ -d "$build/python/iaa" ]; then
  site="$(cd "$prefix" && ls -d lib/python3*/*-packages)"
  [ -e "$prefix/$site/iaa/__init__.pyi" ] || fail "the Python package lacks its stub"
  (cd "$tmp" && PYTHONPATH="$prefix/$site" /usr/bin/python3 -c "
import iaa, sys
assert iaa.__file__.startswith('$prefix'), iaa.__file__
r = iaa.render(iaa.load_scene('$prefix/share/iaa/scenes/teardrop.toml'), width=24, height=16)
print('python: installed iaa', iaa.__version__, 'renders', r.image.shape)
") || fail "the installed Python package"
fi

# 4. The Debian package.
(cd "$build" && cpack -G DEB -B "$tmp/pkg" >"$tmp/cpack.log" 2>&1) ||
  { cat "$tmp/cpack.log"; fail "cpack -G DEB"; }
deb="$(ls "$tmp"/pkg/*.deb)"
dpkg-deb --info "$deb" | grep -E "Package|Version|Depends" | sed 's/^/deb: /'
dpkg-deb -x "$deb" "$tmp/root"
scene="$tmp/root/usr/share/iaa/scenes/teardrop.toml"
"$tmp/root/usr/bin/iaa" render "$scene" -o "$tmp/deb.png" --width 64 --height 64 -q ||
  fail "the packaged iaa does not render the demo scene"
"$build/bin/iaa" render "$src/data/scenes/teardrop.toml" -o "$tmp/build.png" --width 64 \
  --height 64 -q
cmp -s "$tmp/deb.png" "$tmp/build.png" || fail "the packaged iaa renders other bytes than the build's"
echo "deb: $(basename "$deb") ($(du -k "$deb" | cut -f1) KiB): its iaa renders the teardrop" \
  "as the build's does"
if [ -e "$build/bin/libiaa_vtk.so" ]; then
  vtu_check "$tmp/root/usr/bin/iaa" || fail "the packaged iaa does not write a .vtu through its plugin"
  dpkg-deb --field "$deb" Depends | grep -q libvtk ||
    fail "the package does not depend on VTK's libraries (its plugin needs them)"
  echo "deb: its iaa writes .vtu files through its plugin; the package depends on VTK"
fi
