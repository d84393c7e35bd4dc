# Meshing the teardrop with the octree mesher (from the guaranteed enclosure) and with CGAL Mesh_3,
# then setting both meshes against the IAA render: what each mesh lost, side by side.
set -euo pipefail
scene="$root/data/scenes/teardrop.toml"
echo "== iaa mesh: the teardrop with the octree mesher and with CGAL Mesh_3 (resolution 256)"
"$bin/iaa" mesh "$scene" --method octree -o "$out/teardrop-octree.ply" --report "$out/teardrop-octree.json" -q
"$bin/iaa" mesh "$scene" --method cgal -o "$out/teardrop-cgal.ply" --report "$out/teardrop-cgal.json" -q
echo "== iaa compare: each mesh against the IAA certificates of the teardrop's view"
for m in octree cgal; do
  "$bin/iaa" compare "$scene" --mesh "$out/teardrop-$m.ply" -o "$out/teardrop-$m-diff.png" \
    --report "$out/teardrop-$m-diff.json" -q > /dev/null
done
count() { grep -o "\"$2\": [0-9]*" "$out/teardrop-$1-diff.json" | grep -o '[0-9]*$'; }
tris() { grep -o '"triangles": [0-9]*' "$out/teardrop-$1.json" | grep -o '[0-9]*$'; }
printf '%-8s %10s %12s %12s\n' method triangles "lost pixels" "wrong pixels"
for m in octree cgal; do
  printf '%-8s %10s %12s %12s\n' "$m" "$(tris $m)" "$(count $m lost)" "$(count $m wrong)"
done
echo "(diff pictures: $out/teardrop-octree-diff.png, $out/teardrop-cgal-diff.png; red = lost, blue = wrong)"
