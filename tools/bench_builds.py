#!/usr/bin/env python3
"""Times `iaa render` of two builds of iaa on the same scenes, runs taking turns (old, new, old,
new, ...), and prints each build's median wall time and the ratio old/new (the speed-up).

Issue 16's speed targets are ratios against an older commit measured this way on one machine:
build that commit in a worktree (`git worktree add --detach ../iaa-old COMMIT`, then
`cmake -S ../iaa-old -B ../iaa-old/build -G Ninja -DCMAKE_BUILD_TYPE=Release` and
`cmake --build ../iaa-old/build --target iaa` (`iaa_cli` in older trees)) and pass both binaries.

Usage: tools/bench_builds.py OLD_IAA NEW_IAA [NAME ...] [--scenes DIR] [--runs N] [--size S]
                             [--threads T] [--json FILE]
With no NAME, every scene of the directory (NAME.toml) in name order. The same scene file is given
to both builds. A scene that either build fails to render is reported and skipped."""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    ap.add_argument('old')
    ap.add_argument('new')
    ap.add_argument('names', nargs='*')
    ap.add_argument('--scenes', default=os.path.join(here, '..', 'data', 'scenes'))
    ap.add_argument('--runs', type=int, default=5)
    ap.add_argument('--size', type=int, default=500)
    ap.add_argument('--threads', type=int, default=2)
    ap.add_argument('--json')
    a = ap.parse_args()
    if a.runs < 1 or a.size < 1 or a.threads < 0:
        sys.exit('--runs and --size must be at least 1, --threads at least 0')
    for b in (a.old, a.new):
        if not os.access(b, os.X_OK):
            sys.exit(f'not an executable: {b}')
    names = a.names or sorted(f[:-5] for f in os.listdir(a.scenes) if f.endswith('.toml'))
    tmp = tempfile.mkdtemp()
    rows = []
    print(f"{'scene':16s} {'old s':>8s} {'new s':>8s} {'old/new':>8s}", flush=True)
    for n in names:
        scene = os.path.join(a.scenes, n + '.toml')
        times = {'old': [], 'new': []}
        failed = None
        for _ in range(a.runs):
            for which, exe in (('old', a.old), ('new', a.new)):
                cmd = [exe, 'render', scene, '-o', os.path.join(tmp, which + '.png'), '-q',
                       '--width', str(a.size), '--height', str(a.size), '--threads', str(a.threads)]
                t = time.perf_counter()
                r = subprocess.run(cmd, capture_output=True)
                times[which].append(time.perf_counter() - t)
                if r.returncode != 0:
                    failed = f'{which} build failed: ' + r.stderr.decode(errors='replace')[-300:]
                    break
            if failed:
                break
        if failed:
            print(f'{n:16s} skipped: {failed.strip()}', flush=True)
            continue
        mo, mn = statistics.median(times['old']), statistics.median(times['new'])
        rows.append({'scene': n, 'old_s': mo, 'new_s': mn, 'speedup': mo / mn})
        print(f'{n:16s} {mo:8.3f} {mn:8.3f} {mo / mn:7.2f}x', flush=True)
    if rows:
        print(f"median speed-up {statistics.median(r['speedup'] for r in rows):.2f}x over "
              f'{len(rows)} scenes; medians of {a.runs} runs, {a.size}x{a.size}, '
              f'{a.threads} threads')
    if a.json:
        tmpjson = a.json + '.tmp'
        with open(tmpjson, 'w') as f:
            json.dump({'runs': a.runs, 'size': a.size, 'threads': a.threads, 'scenes': rows}, f,
                      indent=1)
        os.replace(tmpjson, a.json)


if __name__ == '__main__':
    main()
