#!/usr/bin/env bash
# End-to-end checks of `iaa render`, `iaa enclose` and `iaa mesh` under mpirun (docs/distributed.md):
# the outputs of -np 2 and -np 3 --oversubscribe are the same bytes as one process's; bad input is
# reported once, every process exits non-zero and no file is left; a killed process makes the run
# fail quickly with no file. Skipped (exit 0) when there is no mpirun or this iaa has no MPI.
# Every mpirun runs under `timeout`, so that a hang fails the test instead of blocking CI.
# $1 = bin directory, $2 = source directory.
set -uo pipefail
bin="$1"
src="$2"
iaa="$bin/iaa"
if ! command -v mpirun >/dev/null 2>&1; then
  echo "mpi_cli: skipped (no mpirun; tools/setup.sh installs openmpi-bin)"
  exit 0
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
fail=0
# OpenMPI refuses to run as root unless told twice.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpi() {  # mpi NP COMMAND...: mpirun -np NP (oversubscribed above 2), at most 120 s
  local np="$1"; shift
  local over=()
  [ "$np" -gt 2 ] && over=(--oversubscribe)
  timeout -k 5 120 mpirun -np "$np" "${over[@]}" "$@"
}
probe="$(mpi 1 "$iaa" render --help 2>&1)"
if grep -q "built without MPI" <<< "$probe"; then
  echo "mpi_cli: skipped (this iaa was built without MPI)"
  exit 0
fi

ok() {  # ok DESCRIPTION COMMAND...
  local what="$1"; shift
  if ! "$@" >"$tmp/out.txt" 2>&1; then
    echo "FAIL: $what: command failed: $*"; cat "$tmp/out.txt"; fail=1
  fi
}
same() {  # same DESCRIPTION FILE-A FILE-B
  cmp -s "$2" "$3" || { echo "FAIL: $1: $2 and $3 differ"; fail=1; }
}
# bad DESCRIPTION EXPECTED-TEXT COMMAND...: fails, says the text exactly once, leaves no file in
# $tmp/bad (outputs of bad runs go there).
bad() {
  local what="$1" text="$2"; shift 2
  rm -rf "$tmp/bad"; mkdir -p "$tmp/bad"
  if "$@" >"$tmp/out.txt" 2>&1; then
    echo "FAIL: $what: expected an error: $*"; fail=1
  fi
  local n
  n=$(grep -ci -- "$text" "$tmp/out.txt")
  if [ "$n" -ne 1 ]; then
    echo "FAIL: $what: '$text' said $n times, not once:"; cat "$tmp/out.txt"; fail=1
  fi
  if [ -n "$(ls -A "$tmp/bad")" ]; then echo "FAIL: $what: left files: $(ls -A "$tmp/bad")"; fail=1; fi
}

# --- render: the image, the AOVs and the counts are one process's, for any N and thread count.
scene="$src/data/scenes/teardrop.toml"
small=(--width 150 --height 110 -q)
ok "render, one process" "$iaa" render "$scene" -o "$tmp/one.png" "${small[@]}" --aov "$tmp/one" --report "$tmp/one.json" --threads 2
ok "render, -np 2" mpi 2 "$iaa" render "$scene" -o "$tmp/np2.png" "${small[@]}" --aov "$tmp/np2" --report "$tmp/np2.json" --threads 1
ok "render, -np 3" mpi 3 "$iaa" render "$scene" -o "$tmp/np3.png" "${small[@]}" --aov "$tmp/np3" --report "$tmp/np3.json" --threads 2
for n in np2 np3; do
  same "render $n image" "$tmp/one.png" "$tmp/$n.png"
  for a in certificate coverage leaves evals; do same "render $n $a" "$tmp/one/$a.png" "$tmp/$n/$a.png"; done
  # The counts agree, and the report has the balance.
  for key in total screen_blocks certified_covered uncertain; do
    a=$(grep -o "\"$key\": [0-9]*" "$tmp/one.json"); b=$(grep -o "\"$key\": [0-9]*" "$tmp/$n.json")
    [ "$a" = "$b" ] || { echo "FAIL: render $n: $key '$a' vs '$b'"; fail=1; }
  done
  grep -q '"max_over_mean_evaluations"' "$tmp/$n.json" || { echo "FAIL: render $n: no balance in the report"; fail=1; }
  grep -q '"idle_seconds"' "$tmp/$n.json" || { echo "FAIL: render $n: no idle times in the report"; fail=1; }
done
grep -q '"processes": 3' "$tmp/np3.json" || { echo "FAIL: render np3: report does not say 3 processes"; fail=1; }
# A window and another method.
ok "render window, one" "$iaa" render "$scene" -o "$tmp/w1.png" "${small[@]}" --window 20,10,130,70 --method adaptive
ok "render window, -np 2" mpi 2 "$iaa" render "$scene" -o "$tmp/w2.png" "${small[@]}" --window 20,10,130,70 --method adaptive --threads 1
same "render window" "$tmp/w1.png" "$tmp/w2.png"
# The summary and the progress are the lead's alone.
ok "render summary" mpi 2 "$iaa" render "$scene" -o "$tmp/s.png" --width 60 --height 40 --threads 1
n=$(grep -c "interval evaluations" "$tmp/out.txt")
[ "$n" -eq 1 ] || { echo "FAIL: render summary printed $n times"; cat "$tmp/out.txt"; fail=1; }
grep -q "MPI: 2 processes" "$tmp/out.txt" || { echo "FAIL: render summary lacks the balance"; cat "$tmp/out.txt"; fail=1; }

# --- enclose: the same boxes (the .vtu bytes); a .pvtu with one piece per process.
chubs="$src/data/scenes/chubs.toml"
if "$iaa" enclose "$chubs" -d 5 -q -o "$tmp/probe.vtu" >/dev/null 2>&1; then
  ok "enclose, one" "$iaa" enclose "$chubs" -d 7 --refine-possible 2 -q -o "$tmp/e1.vtu" --report "$tmp/e1.json"
  ok "enclose, -np 2" mpi 2 "$iaa" enclose "$chubs" -d 7 --refine-possible 2 -q -t 1 -o "$tmp/e2.vtu" --report "$tmp/e2.json"
  ok "enclose, -np 3" mpi 3 "$iaa" enclose "$chubs" -d 7 --refine-possible 2 -q -t 1 -o "$tmp/e3.pvtu"
  same "enclose -np 2 boxes" "$tmp/e1.vtu" "$tmp/e2.vtu"
  for key in boxes evaluations corner_evaluations; do
    a=$(grep -o "^  \"$key\": [0-9]*" "$tmp/e1.json"); b=$(grep -o "^  \"$key\": [0-9]*" "$tmp/e2.json")
    [ "$a" = "$b" ] || { echo "FAIL: enclose -np 2: $key '$a' vs '$b'"; fail=1; }
  done
  boxes=$(grep -o '^  "boxes": [0-9]*' "$tmp/e1.json" | grep -o '[0-9]*$')
  sum=0
  for k in 0 1 2; do
    f="$tmp/e3_$k.vtu"
    [ -s "$f" ] || { echo "FAIL: enclose -np 3: piece $f missing"; fail=1; continue; }
    c=$(grep -a -o 'NumberOfCells="[0-9]*"' "$f" | head -1 | grep -o '[0-9]*')
    sum=$((sum + c))
    grep -q "e3_$k.vtu" "$tmp/e3.pvtu" || { echo "FAIL: enclose -np 3: the .pvtu does not name piece $k"; fail=1; }
  done
  [ "$sum" = "$boxes" ] || { echo "FAIL: enclose -np 3: pieces hold $sum boxes, one process $boxes"; fail=1; }
  ls -a "$tmp" | grep -q '\.parts$' && { echo "FAIL: enclose -np 3: left its temporary directory"; fail=1; }
  # Too many boxes: found while the processes share the work, reported once.
  bad "enclose max-boxes" "max-boxes 1000" mpi 2 "$iaa" enclose "$chubs" -d 8 --max-boxes 1000 -q -t 1 -o "$tmp/bad/e.pvtu"
else
  echo "mpi_cli: enclose .vtu checks skipped (this iaa was built without VTK)"
fi

# --- mesh: the octree mesher's enclosure and the certified mesher's refinement are shared; the
# mesh, its topology and its report are one process's (the report but for its times and the
# balance). The certified runs go without the proof cache, so that their counts of evaluations
# are exact too; with the cache (the last run) the hits depend on which thread meets which cell,
# and the cache only saves work.
# stable REPORT: the report without those keys, one key per line.
stable() {
  python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
for k in ("seconds", "mpi", "mesh_file"):
    j.pop(k, None)
for k in list(j["settings"]):
    if k.startswith("seconds_"):
        del j["settings"][k]
print(json.dumps(j, indent=1, sort_keys=True))' "$1"
}
evals() { grep -o '"interval_evaluations": [0-9]*' "$1" | grep -o '[0-9]*$'; }
if "$iaa" mesh "$chubs" --method octree --depth 4 -q -o "$tmp/probe.ply" >/dev/null 2>&1; then
  ok "mesh, one" "$iaa" mesh "$chubs" --method octree --depth 6 -q -o "$tmp/m1.ply"
  ok "mesh, -np 2" mpi 2 "$iaa" mesh "$chubs" --method octree --depth 6 -q --threads 1 -o "$tmp/m2.ply"
  same "mesh -np 2" "$tmp/m1.ply" "$tmp/m2.ply"
  certified=(mesh "$chubs" --min-depth 5 -q --no-proof-cache)
  ok "mesh certified, one" "$iaa" "${certified[@]}" --threads 2 -o "$tmp/c1.ply" --report "$tmp/c1.json"
  ok "mesh certified, -np 2" mpi 2 "$iaa" "${certified[@]}" --threads 1 -o "$tmp/c2.ply" --report "$tmp/c2.json"
  ok "mesh certified, -np 3" mpi 3 "$iaa" "${certified[@]}" --threads 2 -o "$tmp/c3.ply" --report "$tmp/c3.json"
  stable "$tmp/c1.json" > "$tmp/c1.stable"
  for n in c2 c3; do
    same "mesh certified $n" "$tmp/c1.ply" "$tmp/$n.ply"
    stable "$tmp/$n.json" > "$tmp/$n.stable"
    same "mesh certified $n report" "$tmp/c1.stable" "$tmp/$n.stable"
    grep -q '"max_over_mean_evaluations"' "$tmp/$n.json" || { echo "FAIL: mesh certified $n: no balance in the report"; fail=1; }
  done
  ok "mesh certified, -np 2, proof cache" mpi 2 "$iaa" mesh "$chubs" --min-depth 5 -q --threads 1 -o "$tmp/c4.ply" --report "$tmp/c4.json"
  same "mesh certified with the proof cache" "$tmp/c1.ply" "$tmp/c4.ply"
  [ "$(evals "$tmp/c4.json")" -le "$(evals "$tmp/c1.json")" ] ||
    { echo "FAIL: mesh certified: $(evals "$tmp/c4.json") evaluations with the proof cache, $(evals "$tmp/c1.json") without"; fail=1; }
else
  echo "mpi_cli: mesh checks skipped (this iaa was built without OpenMesh)"
fi

# --- bad input: one message, every process non-zero, no file.
bad "missing scene" "cannot read" mpi 2 "$iaa" render "$tmp/nope.toml" -o "$tmp/bad/a.png"
bad "bad key" "camera.fovy" mpi 3 "$iaa" render "$scene" -o "$tmp/bad/a.png" --set camera.fovy=3
bad "unwritable output" "cannot write" mpi 2 "$iaa" render "$scene" -o "$tmp/bad/no/such/dir/a.png"
bad "bad depth" "depth" mpi 2 "$iaa" enclose "$chubs" -d 0 -o "$tmp/bad/e.vtu"
bad "command without MPI" "does not run under mpirun" mpi 2 "$iaa" eval 'x+y' --box 0:1,0:1,0:1
bad "usage error" "--nope" mpi 2 "$iaa" render "$scene" -o "$tmp/bad/a.png" --nope

# --- a process that fails in the middle of the run (on purpose, IAA_TEST_FAIL_RANK: a test hook
# of the iaa command, tools/iaa/command_spread.h): the run ends within seconds, the failed process
# alone says why, naming its rank, every process exits non-zero, and no file is left.
for who in 1 0; do
  start=$(date +%s)
  IAA_TEST_FAIL_RANK=$who bad "rank $who fails" "(IAA_TEST_FAIL_RANK=$who)" mpi 3 "$iaa" render "$chubs" -o "$tmp/bad/f.png" --width 1500 --height 1500 --threads 1 -q
  took=$(( $(date +%s) - start ))
  [ "$took" -le 15 ] || { echo "FAIL: rank $who fails: the run took $took s"; fail=1; }
  grep -q "MPI rank $who" "$tmp/out.txt" || { echo "FAIL: rank $who fails: the message does not name the rank"; cat "$tmp/out.txt"; fail=1; }
done
IAA_TEST_FAIL_RANK=2 bad "mesh, rank 2 fails" "(IAA_TEST_FAIL_RANK=2)" mpi 3 "$iaa" mesh "$chubs" --min-depth 5 -q --threads 1 -o "$tmp/bad/f.ply" --report "$tmp/bad/f.json"

# --- a killed process: the run fails within seconds, says so, and leaves no file.
big=(--width 1500 --height 1500 --threads 1 -q)
rm -rf "$tmp/bad"; mkdir -p "$tmp/bad"
descendants() {  # descendants PID: every process below PID (by parent PID)
  local c
  for c in $(pgrep -P "$1"); do echo "$c"; descendants "$c"; done
}
mpi 2 "$iaa" render "$chubs" -o "$tmp/bad/big.png" "${big[@]}" >"$tmp/kill.txt" 2>&1 &
runner=$!
victim=""
for _ in $(seq 100); do  # up to 10 s for the ranks to start
  for p in $(descendants "$runner"); do
    if tr '\0' '\n' < "/proc/$p/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1"; then
      victim=$p
    fi
  done
  [ -n "$victim" ] && break
  sleep 0.1
done
if [ -z "$victim" ]; then
  echo "FAIL: killed rank: did not find rank 1 of the run"; fail=1
  wait "$runner"
else
  sleep 0.5
  kill -9 "$victim"
  killed=$(date +%s)
  wait "$runner"; rc=$?
  took=$(( $(date +%s) - killed ))
  [ "$rc" -ne 0 ] || { echo "FAIL: killed rank: the run succeeded"; fail=1; }
  [ "$took" -le 10 ] || { echo "FAIL: killed rank: the run ended $took s after the kill (rc $rc)"; fail=1; }
  grep -qiE "signal|killed" "$tmp/kill.txt" || { echo "FAIL: killed rank: no clear message:"; cat "$tmp/kill.txt"; fail=1; }
  [ -z "$(ls -A "$tmp/bad")" ] || { echo "FAIL: killed rank: left files: $(ls -A "$tmp/bad")"; fail=1; }
fi

[ "$fail" -eq 0 ] && echo "mpi_cli: all checks passed"
exit "$fail"
