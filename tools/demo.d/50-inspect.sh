# Why one pixel of the teardrop looks as it does: `iaa inspect` replays the renderer's own path for
# a pixel on the thin neck (256,250: the x axis projects onto row 250, and the neck is thinner than
# a pixel for columns ~250..271), prints the tree of its beams and depth tests, writes it as JSON
# and as a VTK multiblock, and `iaa-viz` draws the multiblock to a PNG (its own Xvfb, no display).
set -euo pipefail
scene="$root/data/scenes/teardrop.toml"
pixel=256,250
echo "== iaa inspect: the teardrop's neck pixel $pixel (beams, depth tests, decisions)"
"$bin/iaa" inspect "$scene" --pixel "$pixel" > "$out/inspect-neck.txt"
"$bin/iaa" inspect "$scene" --pixel "$pixel" --json > "$out/inspect-neck.json"
head -n 2 "$out/inspect-neck.txt"
grep -E '^ *#[0-9]+ |decision ' "$out/inspect-neck.txt" | sed -n '11,22p'
echo "   ... (whole tree: $out/inspect-neck.txt, as JSON: $out/inspect-neck.json)"
if [ -x "$bin/iaa-viz" ] && { [ -n "${DISPLAY:-}" ] || command -v Xvfb >/dev/null; }; then
  "$bin/iaa" inspect "$scene" --pixel "$pixel" --vtk "$out/inspect-neck.vtm" | tail -n 1
  "$bin/iaa-viz" "$out/inspect-neck.vtm" --size 960x640 \
    --title "teardrop: the neck pixel $pixel (iaa inspect --vtk)" -o "$out/inspect-teardrop-neck.png"
  echo "picture: $out/inspect-teardrop-neck.png (beams, hit slabs, depth boxes, normals, mesh)"
else
  echo "(no picture: iaa-viz was not built or neither a display nor Xvfb is available)"
fi
