# The teardrop's expression near its thin neck: the interval value over a box around the neck.
set -euo pipefail
echo "== iaa eval: the teardrop's expression around its thin neck"
"$bin/iaa" eval '0.5*x^5 + 0.5*x^4 - y^2 - z^2' --at -0.05,0,0 --box -0.05:0.05,-0.01:0.01,-0.01:0.01
