#!/usr/bin/env bash
# End-to-end checks of `iaa eval`: outputs, and clear errors with non-zero exits on bad input.
# Usage: eval_cli.sh BIN_DIR SOURCE_DIR
set -uo pipefail
bin="$1"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail=0
check() {  # check NAME EXPECTED_EXIT EXPECTED_TEXT -- command...
  local name="$1" want_rc="$2" want="$3"
  shift 4
  local out rc
  out="$("$@" 2>&1)"
  rc=$?
  if [ "$rc" != "$want_rc" ] && ! { [ "$want_rc" = "nonzero" ] && [ "$rc" != 0 ]; }; then
    echo "FAIL $name: exit $rc, wanted $want_rc"; echo "$out" | head -5; fail=1; return
  fi
  if ! grep -qF -- "$want" <<<"$out"; then
    echo "FAIL $name: output lacks '$want'"; echo "$out" | head -5; fail=1; return
  fi
  echo "ok   $name"
}
iaa="$bin/iaa"
check point 0 "f       = 0.3125" -- "$iaa" eval 'x^2 + y^2 + z^2 - 1' --at 1,0.5,0.25
check gradient 0 "grad f  = (2, 1, 0.5)" -- "$iaa" eval 'x^2 + y^2 + z^2 - 1' --at 1,0.5,0.25
check box-empty 0 "certified empty" -- "$iaa" eval 'x^2 + y^2 + z^2 - 1' --box 2:3,0:1,0:1
check box-possible 0 "possible" -- "$iaa" eval 'x^2 + y^2 + z^2 - 1' --box 0:1,0:1,0:1
check tape 0 "square" -- "$iaa" eval 'x^2 + 1' --tape
check param 0 "f       = 0" -- "$iaa" eval 'x^2 - r^2' --param r=0.5 --at 0.5,0,0
check partial 0 "partial domain" -- "$iaa" eval 'sqrt(x) - 1' --box -1:4,0:0,0:0
check empty-text 1 "line 1, column 1: expected an expression" -- "$iaa" eval ''
check unknown-name 1 "unknown name 'foo'" -- "$iaa" eval 'x + foo'
check arity 1 "sqrt takes 1 argument, got 2" -- "$iaa" eval 'sqrt(x, y)'
check unbalanced 1 "')' to close" -- "$iaa" eval '(x + 1'
check huge-power 1 "too large" -- "$iaa" eval 'x^1000000'
check negative-power 1 "x^(-3)" -- "$iaa" eval 'x^-3'
check inf-literal 1 "too large for a double" -- "$iaa" eval '1e400 * x'
check nan-name 1 "unknown name 'nan'" -- "$iaa" eval 'nan'
check nonfinite-box 1 "not a finite number" -- "$iaa" eval 'x' --box nan:1,0:1,0:1
check inverted-box 1 "inverted" -- "$iaa" eval 'x' --box 1:0,0:1,0:1
check bad-point 1 "expected three numbers" -- "$iaa" eval 'x' --at 1,2
check missing-file 1 "cannot read" -- "$iaa" eval --file "$tmp/none.txt"
python3 -c 'print("(" * 100000 + "x" + ")" * 100000)' > "$tmp/deep.txt"
check deep-nesting 1 "nested too deeply" -- "$iaa" eval --file "$tmp/deep.txt" --at 0,0,0
# A long flat expression evaluates in linear time and memory (the printed expression is cut):
# 100 000 terms under a 2 GB address-space limit (printing it once took 4.7 GB for 30 000).
python3 -c 'print(" + ".join(["x"] * 100000))' > "$tmp/sum.txt"
check long-sum 0 "f       = 100000" -- bash -c 'ulimit -v 2000000 && "$0" eval --file "$1" --at 1,0,0' \
  "$iaa" "$tmp/sum.txt"
check long-sum-box 0 "F       = [50000, 100000]" -- bash -c \
  'ulimit -v 2000000 && "$0" eval --file "$1" --box 0.5:1,0:0,0:0' "$iaa" "$tmp/sum.txt"
check long-sum-cut 0 "(the first 2000 characters" -- bash -c \
  'ulimit -v 2000000 && "$0" eval --file "$1"' "$iaa" "$tmp/sum.txt"
check help 0 "Examples:" -- "$iaa" eval --help
# bench tape says whether interval evaluation meets its target (the verdict, not the speed, is
# checked: speed is measured, not asserted).
check bench-tape-target 0 "target: interval within 4x" -- "$iaa" bench tape --points 100 --runs 1 \
  --json "$tmp/tape.json"
check bench-tape-json 0 '"within_target"' -- cat "$tmp/tape.json"
check bench-tape-batch-json 0 '"batch_within_target"' -- cat "$tmp/tape.json"
check bench-tape-point-batch-json 0 '"point_batch_over_point"' -- cat "$tmp/tape.json"
check no-command nonzero "subcommand is required" -- "$iaa"
exit $fail
