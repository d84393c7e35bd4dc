#!/usr/bin/env bash
# iaa enclose on bad input: a clear message, a non-zero exit code and no output file; an
# expression with no zero in the box is a valid, empty result. $1 = bin dir, $2 = source dir.
set -uo pipefail
bin="$1"
tmp="$(mktemp -d)"
trap 'chmod -R u+w "$tmp"; rm -rf "$tmp"' EXIT
fail=0
sphere=(--expr 'x^2 + y^2 + z^2 - 0.5' --bounds -1:1,-1:1,-1:1)

# expect_error MESSAGE-PATTERN ARGS...: exit code 1, the message on stderr, no .vtu left behind.
expect_error() {
  local pattern="$1"
  shift
  "$bin/iaa" enclose "$@" -q -o "$tmp/out.vtu" > /dev/null 2> "$tmp/err.txt"
  local rc=$?
  if [[ $rc -ne 1 ]] || ! grep -q -- "$pattern" "$tmp/err.txt" || ls "$tmp" | grep -q vtu; then
    echo "FAIL (rc=$rc): iaa enclose $* -> $(cat "$tmp/err.txt")"
    fail=1
  fi
}

expect_error "--depth must be between 1 and 21, got 0" "${sphere[@]}" --depth 0
expect_error "--depth must be between 1 and 21, got 30" "${sphere[@]}" --depth 30
expect_error "--refine-possible must be between 0 and 8" "${sphere[@]}" --refine-possible 9
expect_error "--max-boxes 100 exceeded" "${sphere[@]}" --depth 6 --max-boxes 100
expect_error "the y range 1:1 is empty" --expr 'x' --bounds -1:1,1:1,-1:1
expect_error "the z range 1:-1 is inverted" --expr 'x' --bounds -1:1,-1:1,1:-1
expect_error "expected three ranges" --expr 'x' --bounds -1:1,-1:1
expect_error "line 1, column" --expr 'x^2 + * y' --bounds -1:1,-1:1,-1:1
expect_error "no surface" --depth 3
expect_error "f is undefined (NaN) everywhere in the bounds" --expr "sqrt(-1 - x^2) - 1" --bounds -1:1,-1:1,-1:1
expect_error "cannot read" "$tmp/no-such-scene.toml"

# Unwritable outputs: a missing directory, a read-only one (skipped as root, who may write there),
# ones no one can write, root included (a parent that is a regular file, an output that is a
# directory, a report under a regular file), a wrong extension.
"$bin/iaa" enclose "${sphere[@]}" -d 3 -q -o "$tmp/missing/out.vtu" > /dev/null 2> "$tmp/err.txt"
[[ $? -eq 1 ]] && grep -q "does not exist" "$tmp/err.txt" || { echo "FAIL: missing directory"; fail=1; }
mkdir "$tmp/ro" && chmod a-w "$tmp/ro"
if [[ $(id -u) -ne 0 ]]; then
  "$bin/iaa" enclose "${sphere[@]}" -d 3 -q -o "$tmp/ro/out.vtu" > /dev/null 2> "$tmp/err.txt"
  [[ $? -eq 1 ]] && grep -q "not writable" "$tmp/err.txt" || { echo "FAIL: read-only directory"; fail=1; }
fi
mkdir "$tmp/w" && touch "$tmp/w/file" && mkdir "$tmp/w/dir.vtu"
# expect_unwritable WHAT PATTERN ARGS...: exit code 1, the message, and $tmp/w unchanged.
expect_unwritable() {
  local what="$1" pattern="$2"
  shift 2
  "$bin/iaa" enclose "${sphere[@]}" -d 3 -q "$@" > /dev/null 2> "$tmp/err.txt"
  local rc=$?
  local left
  left="$(cd "$tmp/w" && find . -mindepth 1 | sort | tr '\n' ' ')"
  if [[ $rc -ne 1 ]] || ! grep -q -- "$pattern" "$tmp/err.txt" || [[ "$left" != "./dir.vtu ./file " ]] ||
    [[ -s "$tmp/w/file" ]]; then
    echo "FAIL (rc=$rc): $what -> $(cat "$tmp/err.txt") [left: $left]"
    fail=1
  fi
}
expect_unwritable "parent is a file" "cannot write '$tmp/w/file/out.vtu'" -o "$tmp/w/file/out.vtu"
expect_unwritable "output is a directory" "cannot write '$tmp/w/dir.vtu'" -o "$tmp/w/dir.vtu"
expect_unwritable "report under a file" "cannot write '$tmp/w/file/r.json'" \
  -o "$tmp/w/out.vtu" --report "$tmp/w/file/r.json"
"$bin/iaa" enclose "${sphere[@]}" -d 3 -q -o "$tmp/out.png" > /dev/null 2> "$tmp/err.txt"
[[ $? -eq 1 ]] && grep -q "must be a .vtu" "$tmp/err.txt" || { echo "FAIL: wrong extension"; fail=1; }

# No zero in the box: exit 0, a clear message, a valid empty file.
"$bin/iaa" enclose --expr 'x^2 + y^2 + z^2 + 1' --bounds -1:1,-1:1,-1:1 -d 4 -q \
  -o "$tmp/empty.vtu" > "$tmp/out.txt" 2>&1
[[ $? -eq 0 ]] && grep -q "certified empty" "$tmp/out.txt" && test -s "$tmp/empty.vtu" \
  || { echo "FAIL: empty result: $(cat "$tmp/out.txt")"; fail=1; }

[[ $fail -eq 0 ]] && echo "enclose_errors: ok"
exit $fail
