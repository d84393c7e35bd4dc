#!/usr/bin/env bash
# A command that needs a library this build left out (IAA_WITH_CGAL / IAA_WITH_OPENMESH /
# IAA_WITH_VTK / IAA_WITH_MPI=OFF) fails with exit status 1, one message naming the option, and no file.
# Which libraries are out is read from the build's CMakeCache.txt (next to bin/), not guessed from
# the binary's behaviour; in a full build there is nothing to check. tools/test.sh runs it on the
# clang build with all three off. $1 = bin directory, $2 = source directory.
set -uo pipefail
bin="$1"
src="$2"
cache="$bin/../CMakeCache.txt"
[[ -f "$cache" ]] || { echo "FAIL: no CMakeCache.txt next to $bin"; exit 1; }
off() { grep -q "^$1:BOOL=OFF$" "$cache"; }
if ! off IAA_WITH_CGAL && ! off IAA_WITH_OPENMESH && ! off IAA_WITH_VTK && ! off IAA_WITH_MPI; then
  echo "disabled_cli: nothing to check (CGAL, OpenMesh, VTK and MPI are all in this build)"
  exit 0
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail=0
sphere=(--expr 'x^2 + y^2 + z^2 - 0.5' --bounds -1:1,-1:1,-1:1)

# expect_disabled OPTION ARGS...: exit status 1, "OPTION=OFF" on stderr, nothing in $tmp/out.
expect_disabled() {
  local option="$1"
  shift
  mkdir -p "$tmp/out"
  "$bin/iaa" "$@" > "$tmp/stdout" 2> "$tmp/stderr"
  local rc=$?
  if [[ $rc -ne 1 ]] || ! grep -q -- "$option=OFF" "$tmp/stderr" ||
    [[ $(wc -l < "$tmp/stderr") -ne 1 ]] || [[ -n "$(ls -A "$tmp/out")" ]]; then
    echo "FAIL (rc=$rc): iaa $* -> $(cat "$tmp/stderr") [files: $(ls -A "$tmp/out")]"
    fail=1
  fi
  rm -rf "$tmp/out"
}

checked=0
if off IAA_WITH_CGAL; then
  expect_disabled IAA_WITH_CGAL mesh "${sphere[@]}" --method cgal -o "$tmp/out/m.ply" \
    --report "$tmp/out/m.json"
  expect_disabled IAA_WITH_CGAL compare "$src/data/scenes/teardrop.toml" --mesh "$src/none.ply" \
    -o "$tmp/out/d.png" --report "$tmp/out/d.json"
  checked=$((checked + 2))
fi
if off IAA_WITH_VTK; then
  expect_disabled IAA_WITH_VTK mesh "${sphere[@]}" --method vtk -o "$tmp/out/m.ply" \
    --report "$tmp/out/m.json"
  expect_disabled IAA_WITH_VTK enclose "${sphere[@]}" --depth 3 -q -o "$tmp/out/x.vtu" \
    --report "$tmp/out/x.json"
  checked=$((checked + 2))
fi
if off IAA_WITH_OPENMESH; then
  expect_disabled IAA_WITH_OPENMESH mesh "${sphere[@]}" --method octree -o "$tmp/out/m.ply" \
    --report "$tmp/out/m.json"
  expect_disabled IAA_WITH_OPENMESH compare "$src/data/scenes/teardrop.toml" \
    --mesh "$src/none.ply" -o "$tmp/out/d.png"
  checked=$((checked + 2))
fi
if off IAA_WITH_MPI; then
  # Started by mpirun (as its environment says) without MPI: refused rather than run N times.
  mkdir -p "$tmp/out"
  OMPI_COMM_WORLD_SIZE=2 OMPI_COMM_WORLD_RANK=0 "$bin/iaa" render \
    "$src/data/scenes/teardrop.toml" -o "$tmp/out/a.png" > "$tmp/stdout" 2> "$tmp/stderr"
  rc=$?
  if [[ $rc -ne 1 ]] || ! grep -q "IAA_WITH_MPI=OFF" "$tmp/stderr" ||
    [[ $(wc -l < "$tmp/stderr") -ne 1 ]] || [[ -n "$(ls -A "$tmp/out")" ]]; then
    echo "FAIL (rc=$rc): iaa render under mpirun without MPI -> $(cat "$tmp/stderr")"
    fail=1
  fi
  rm -rf "$tmp/out"
  checked=$((checked + 1))
fi

# The rest of the tool still works in this build: the failures above are the options', not a
# broken binary's.
"$bin/iaa" enclose "${sphere[@]}" --depth 3 -q > "$tmp/stdout" 2> "$tmp/stderr" ||
  { echo "FAIL: iaa enclose without -o: $(cat "$tmp/stderr")"; fail=1; }
"$bin/iaa" mesh "${sphere[@]}" --method dc -o "$tmp/m.ply" > /dev/null 2> "$tmp/stderr"
[[ $? -eq 1 ]] && grep -q "unknown mesher" "$tmp/stderr" ||
  { echo "FAIL: unknown mesher: $(cat "$tmp/stderr")"; fail=1; }

[[ $fail -eq 0 ]] && echo "disabled_cli: ok ($checked commands refused with the option named)"
exit $fail
