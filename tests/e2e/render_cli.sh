#!/usr/bin/env bash
# End-to-end checks of `iaa render`: outputs on success, and for bad input a clear error, a
# non-zero exit code and no output file.
set -uo pipefail
bin="$1"
src="$2"
iaa="$bin/iaa"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail=0

ok() {  # ok DESCRIPTION COMMAND...
  local what="$1"; shift
  if ! "$@" >"$tmp/out.txt" 2>&1; then
    echo "FAIL: $what: command failed: $*"; cat "$tmp/out.txt"; fail=1
  fi
}
bad() {  # bad DESCRIPTION EXPECTED-TEXT COMMAND...  (must fail, mention the text, write no image)
  local what="$1" text="$2"; shift 2
  rm -f "$tmp/bad.png"
  if "$@" >"$tmp/out.txt" 2>&1; then
    echo "FAIL: $what: expected an error: $*"; fail=1
  elif ! grep -qi -- "$text" "$tmp/out.txt"; then
    echo "FAIL: $what: message lacks '$text':"; cat "$tmp/out.txt"; fail=1
  fi
  if [ -e "$tmp/bad.png" ]; then echo "FAIL: $what: left an output file"; fail=1; fi
  if ls "$tmp" | grep -q '\.tmp'; then echo "FAIL: $what: left a temporary file"; fail=1; fi
}

scene="$src/data/scenes/teardrop.toml"
small=(--width 40 --height 30 -q)

# Success: image, AOVs and report.
ok "render" "$iaa" render "$scene" -o "$tmp/a.png" "${small[@]}" --aov "$tmp/aov" --report "$tmp/r.json" --threads 1
for f in a.png aov/certificate.png aov/coverage.png aov/leaves.png aov/evals.png r.json; do
  [ -s "$tmp/$f" ] || { echo "FAIL: missing $f"; fail=1; }
done
grep -q '"certified_covered"' "$tmp/r.json" || { echo "FAIL: report lacks pixel classes"; fail=1; }
# The same bytes with two threads.
ok "render 2 threads" "$iaa" render "$scene" -o "$tmp/b.png" "${small[@]}" --aov "$tmp/aov2" --threads 2
cmp -s "$tmp/a.png" "$tmp/b.png" || { echo "FAIL: image differs between 1 and 2 threads"; fail=1; }
cmp -s "$tmp/aov/certificate.png" "$tmp/aov2/certificate.png" || { echo "FAIL: certificate differs"; fail=1; }
cmp -s "$tmp/aov/evals.png" "$tmp/aov2/evals.png" || { echo "FAIL: evals AOV differs"; fail=1; }
for m in point adaptive "grid 3"; do
  ok "method $m" "$iaa" render "$scene" -o "$tmp/m.png" "${small[@]}" --method "$m"
done
ok "window" "$iaa" render "$scene" -o "$tmp/w.png" "${small[@]}" --window 5,5,20,15
ok "set" "$iaa" render "$scene" -o "$tmp/s.png" "${small[@]}" --set camera.fov=30 --set render.max_level=1
ok "help" "$iaa" render --help
# Defined only in a small ball that no grid centre of the domain check falls in: not rejected.
ok "defined in a small ball" "$iaa" render "$scene" -o "$tmp/ball.png" "${small[@]}" --set 'surface.expression="sqrt(0.001 - (x-0.3)^2 - (y-0.2)^2 - z^2) - 0.01"'

# Bad input.
bad "missing scene" "cannot read" "$iaa" render "$tmp/nope.toml" -o "$tmp/bad.png"
printf '[surface\nexpression = "x"\n' >"$tmp/malformed.toml"
bad "malformed scene" "malformed.toml" "$iaa" render "$tmp/malformed.toml" -o "$tmp/bad.png"
bad "unknown key" "camera.fovy" "$iaa" render "$scene" -o "$tmp/bad.png" --set camera.fovy=3
bad "eye == look_at" "same point" "$iaa" render "$scene" -o "$tmp/bad.png" --set camera.eye=[-0.05,0,0]
bad "up parallel" "parallel" "$iaa" render "$scene" -o "$tmp/bad.png" --set camera.up=[0.4,0.9,3.0]
bad "fov 0" "\[0.001, 179\]" "$iaa" render "$scene" -o "$tmp/bad.png" --set camera.fov=0
bad "fov 180" "camera.fov" "$iaa" render "$scene" -o "$tmp/bad.png" --set camera.fov=180
bad "zero width" "image.width" "$iaa" render "$scene" -o "$tmp/bad.png" --width 0
bad "huge size" "image.width" "$iaa" render "$scene" -o "$tmp/bad.png" --width 100000 --height 100000
bad "window outside" "window" "$iaa" render "$scene" -o "$tmp/bad.png" "${small[@]}" --window 0,0,41,10
bad "NaN everywhere" "undefined" "$iaa" render "$scene" -o "$tmp/bad.png" --set 'surface.expression="sqrt(-1-x^2)"'
# One interval over the whole box reaches above 0 here; the sub-box scan proves it undefined.
bad "NaN everywhere, x - x" "undefined (NaN) everywhere" "$iaa" render "$scene" -o "$tmp/bad.png" --set 'surface.expression="sqrt(x - x - 1)"'
bad "bad method" "unknown method" "$iaa" render "$scene" -o "$tmp/bad.png" --method raymarch
bad "not png" "png" "$iaa" render "$scene" -o "$tmp/bad.jpg"
bad "bad level" "max_level" "$iaa" render "$scene" -o "$tmp/bad.png" --max-level 9
# A negative value is an error naming the limits, not "not given" (it used to be ignored).
bad "negative level" "max_level must be in \[0, 6\], got -1" "$iaa" render "$scene" -o "$tmp/bad.png" --max-level -1
bad "negative threshold" "estimator_threshold must be in \[0, 2\]" "$iaa" render "$scene" -o "$tmp/bad.png" --threshold -0.5
bad "negative depth tolerance" "depth_tolerance must be in \[0.001, 1000\]" "$iaa" render "$scene" -o "$tmp/bad.png" --depth-tol -1
bad "negative adaptive threshold" "adaptive_threshold must be in \[0, 1\]" "$iaa" render "$scene" -o "$tmp/bad.png" --adaptive-threshold -0.1
bad "negative width" "image.width" "$iaa" render "$scene" -o "$tmp/bad.png" --width -3

exit $fail
