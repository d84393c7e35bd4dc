# Meshing the teardrop with the certified mesher (isotopic to the surface inside the cells it
# certifies, the uncertified ones reported) and with CGAL Mesh_3, then setting both meshes against
# the IAA render: what each mesh lost, side by side.
set -euo pipefail
scene="$root/data/scenes/teardrop.toml"
echo "== iaa mesh: the teardrop with the certified mesher and with CGAL Mesh_3 (resolution 256)"
"$bin/iaa" mesh "$scene" -o "$out/teardrop-certified.ply" --report "$out/teardrop-certified.json" \
  --uncertified "$out/teardrop-uncertified.vtu" -q
"$bin/iaa" mesh "$scene" --method cgal -o "$out/teardrop-cgal.ply" --report "$out/teardrop-cgal.json" -q
echo "== iaa compare: each mesh against the IAA certificates of the teardrop's view"
for m in certified cgal; do
  "$bin/iaa" compare "$scene" --mesh "$out/teardrop-$m.ply" -o "$out/teardrop-$m-diff.png" \
    --report "$out/teardrop-$m-diff.json" -q > /dev/null
done
count() { grep -o "\"$2\": [0-9]*" "$out/teardrop-$1-diff.json" | grep -o '[0-9]*$'; }
field() { grep -o "\"$2\": [0-9a-z]*" "$out/teardrop-$1.json" | head -1 | grep -o '[0-9a-z]*$'; }
printf '%-10s %10s %11s %12s %12s\n' method triangles components "lost pixels" "wrong pixels"
for m in certified cgal; do
  printf '%-10s %10s %11s %12s %12s\n' "$m" "$(field $m triangles)" "$(field $m components)" \
    "$(count $m lost)" "$(count $m wrong)"
done
echo "certified: $(field certified uncertified_cells) uncertified cells (the neck's singular point;" \
  "boxes in $out/teardrop-uncertified.vtu)"
echo "(diff pictures: $out/teardrop-certified-diff.png, $out/teardrop-cgal-diff.png; red = lost, blue = wrong)"
