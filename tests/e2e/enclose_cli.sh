#!/usr/bin/env bash
# iaa enclose end to end: a scene and an expression, .vtu and JSON outputs, same boxes for any
# thread count. Arguments: $1 = bin dir, $2 = source dir.
set -euo pipefail
bin="$1"
src="$2"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

"$bin/iaa" enclose --help | grep -q "Examples:"

# A scene, with its bounds; the report holds the counts.
"$bin/iaa" enclose "$src/data/scenes/teardrop.toml" --depth 5 --refine-possible 2 -q \
  -o "$tmp/teardrop.vtu" --report "$tmp/teardrop.json" > "$tmp/out.txt"
grep -q "crossing (certified surface)" "$tmp/out.txt"
grep -q "wrote        $tmp/teardrop.vtu" "$tmp/out.txt"
test -s "$tmp/teardrop.vtu"
head -c 200 "$tmp/teardrop.vtu" | grep -q 'compressor="vtkLZ4DataCompressor"'
grep -q '"boxes"' "$tmp/teardrop.json"
grep -q '"refine_possible": 2' "$tmp/teardrop.json"

# An expression with a parameter; --cell-size picks the depth.
"$bin/iaa" enclose --expr 'x^2 + y^2 + z^2 - r^2' -p r=0.5 --bounds -1:1,-1:1,-1:1 \
  --cell-size 0.07 -q > "$tmp/sphere.txt"
grep -q "^depth        5 " "$tmp/sphere.txt"

# The boxes do not depend on the thread count.
for t in 1 2; do
  "$bin/iaa" enclose "$src/data/scenes/chubs.toml" -d 5 -t "$t" -q --report "$tmp/c$t.json" > /dev/null
  grep -E '"(boxes|crossing|possible|evaluations|corner_evaluations)"' "$tmp/c$t.json" > "$tmp/c$t.counts"
done
cmp "$tmp/c1.counts" "$tmp/c2.counts"
echo "enclose_cli: ok"
