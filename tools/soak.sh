#!/usr/bin/env bash
# The long run of the guarantees (docs/testing.md, "Soak"), for a machine left alone:
#   nice -n 19 tools/soak.sh [SECONDS]        (default 3600)
# 1. the MPFR check of the interval rules at 10^7 cases (IAA_MPFR_CASES), Release build;
# 2. the property suites at IAA_PROPERTY_SCALE=30 (30x the trials of tools/test.sh), Release build;
# 3. both libFuzzer targets (build-fuzz/: ASan, UBSan), sharing what is left of SECONDS, on corpora
#    kept in build-fuzz/soak/ (a second soak starts where the first stopped).
# Every part runs even when an earlier one fails; the summary at the end has the figures
# docs/testing.md records. Exits non-zero when any part failed.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib/paths.sh"  # root, build, fuzz_build, jobs
total="${1:-3600}"
soak="$fuzz_build/soak"
failed=()
IAA_TARGETS="iaa_core_tests iaa_expr_tests" "$root/tools/build.sh" || exit 1
"$root/tools/build_fuzz.sh" fuzz_parser fuzz_scene || exit 1
start=$(date +%s)  # SECONDS counts from here: the builds are not part of it
mkdir -p "$soak"
summary="$soak/summary.txt"
: >"$summary"
note() { echo "$*" | tee -a "$summary"; }
note "soak: $(date -u +%FT%TZ), ${total}s, $(git -C "$root" rev-parse --short HEAD 2>/dev/null)"

# run NAME COMMAND...: times one part, keeps its log in $soak/NAME.log.
run() {
  local name="$1" t0=$SECONDS
  shift
  if "$@" >"$soak/$name.log" 2>&1; then
    note "$name: passed in $((SECONDS - t0))s"
  else
    note "$name: FAILED after $((SECONDS - t0))s (log: $soak/$name.log)"
    failed+=("$name")
  fi
}
run mpfr env IAA_MPFR_CASES=10000000 "$build/bin/iaa_core_tests" --gtest_filter='*Mpfr*'
run property env IAA_PROPERTY_SCALE=30 "$build/bin/iaa_expr_tests" --gtest_filter='Containment*:*Property*'

left=$((total - ($(date +%s) - start)))
each=$((left > 120 ? left / 2 : 60))
for name in parser scene; do
  mkdir -p "$soak/corpus-$name"
  before=$(ls "$soak/corpus-$name" | wc -l)
  run "fuzz-$name" "$root/tools/fuzz.sh" "$name" "$each" "$soak/corpus-$name"
  cp "$fuzz_build/fuzz-$name.log" "$soak/fuzz-$name.libfuzzer.log" 2>/dev/null
  note "  fuzz_$name: $(grep -E '^stat::number_of_executed_units' "$soak/fuzz-$name.libfuzzer.log" |
    tr -d ' ') corpus $before -> $(ls "$soak/corpus-$name" | wc -l) files;" \
    "last status: $(grep -E '#[0-9]+' "$soak/fuzz-$name.libfuzzer.log" | tail -1)"
done
note "soak: $(( $(date +%s) - start ))s in all; ${#failed[@]} part(s) failed ${failed[*]:-}"
[ ${#failed[@]} -eq 0 ]
