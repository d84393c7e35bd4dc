#!/usr/bin/env bash
# Runs one libFuzzer target of build-fuzz/ (tools/build_fuzz.sh builds it) for SECONDS.
#   tools/fuzz.sh parser|scene SECONDS [CORPUS_DIR]
# Seeds: tests/fuzz/corpus/ (parser); data/scenes/*.toml and tests/fuzz/scene_corpus/ (scene).
# Without CORPUS_DIR the corpus is a temporary copy of the seeds; with it, the directory keeps what
# the run adds (tools/soak.sh). A crash, a leak, undefined behaviour or one input running over 5 s
# fails the run: the log's tail is shown, the input that did it is build-fuzz/fuzz-NAME-*.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib/paths.sh"  # root, build, fuzz_build, jobs
name="$1"
seconds="$2"
corpus="${3:-}"
case "$name" in
  parser) seeds=("$root"/tests/fuzz/corpus/*) max_len=4096 ;;
  scene) seeds=("$root"/data/scenes/*.toml "$root"/tests/fuzz/scene_corpus/*) max_len=8192 ;;
  *) echo "fuzz.sh: unknown fuzzer '$name' (parser or scene)" >&2; exit 2 ;;
esac
if [ -z "$corpus" ]; then
  corpus="$(mktemp -d)"
  trap 'rm -rf "$corpus"' EXIT
fi
mkdir -p "$corpus"
cp "${seeds[@]}" "$corpus"/
log="$fuzz_build/fuzz-$name.log"
echo "fuzz: running fuzz_$name for ${seconds}s"
# UBSan's reports are errors (halt), not messages the fuzzer would ignore.
if ! UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 "$fuzz_build/bin/fuzz_$name" \
  -max_total_time="$seconds" -max_len="$max_len" -timeout=5 -print_final_stats=1 \
  -artifact_prefix="$fuzz_build/fuzz-$name-" "$corpus" 2>"$log"; then
  tail -50 "$log"
  echo "fuzz: fuzz_$name FAILED (log: $log)"
  exit 1
fi
grep -E "^stat::number_of_executed_units|DONE" "$log" || true
echo "fuzz: fuzz_$name: no crash, leak, undefined behaviour or hang"
