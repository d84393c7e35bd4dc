# Renders the default scene (the teardrop, whose neck is thinner than a pixel) with IAA and with
# Whitted's adaptive supersampling, and says where both images are.
set -euo pipefail
scene="$root/data/scenes/teardrop.toml"
echo
echo "== iaa render: the teardrop with IAA (certified) and with adaptive supersampling"
"$bin/iaa" render "$scene" -o "$out/teardrop-iaa.png" --aov "$out/teardrop-iaa-aov" \
  --report "$out/teardrop-iaa.json"
"$bin/iaa" render "$scene" -o "$out/teardrop-adaptive.png" --method adaptive
echo "IAA image:      $out/teardrop-iaa.png (certificate, coverage, leaves, evals in $out/teardrop-iaa-aov/)"
echo "adaptive image: $out/teardrop-adaptive.png"
