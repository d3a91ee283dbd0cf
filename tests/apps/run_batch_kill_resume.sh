#!/usr/bin/env bash
# lidarseg-batch killed with SIGKILL while its jobs run, then started again: the jobs die
# with it, finished runs are not redone (their files are unchanged), every seed ends
# finished, nothing partial is left, and the table is written.
#   run_batch_kill_resume.sh <lidarseg-batch> <worlds dir> <scratch dir>
set -euo pipefail
batch="$1"; worlds="$2"; out="$3"
rm -rf "$out"; mkdir -p "$out"
# Eight runs of 16 m each: when the first has finished, the others are far from done even if
# this script's polling is starved for a few seconds by a loaded machine. (With six runs of
# 10 m the test failed once in the parallel suite, its output lost, and passed in 13 runs
# after it, 12 of them under stress-ng; all runs finishing before the kill is the one
# failure timing can cause, so the margin was widened.)
printf 'speed 1.0\nturn_radius 0.6\nwaypoint 24 0\nwaypoint 34 0\nwaypoint 34 6\n' > "$out/short.traj"
args=(run --world "$worlds/maze.world" --trajectory "$out/short.traj" --seeds 1-8 --jobs 2 --no-icp -q --out "$out/b")
fail() { echo "FAIL: $*"; exit 1; }
# Finished runs only: a run writes its metrics.csv inside run_N.partial before the folder is
# renamed into place, so a glob on run_*/metrics.csv also sees a run still being finished.
finished_runs() { find "$out/b" -mindepth 2 -maxdepth 2 -name metrics.csv -path '*/run_*/*' ! -path '*.partial/*' 2>/dev/null | wc -l; }

"$batch" "${args[@]}" & runner=$!
for _ in $(seq 1 6000); do  # until the first run has finished (at most 10 min, a loaded machine)
  [ "$(finished_runs)" -gt 0 ] && break
  sleep 0.1
done
[ "$(finished_runs)" -gt 0 ] || fail "no run finished"
kill -9 "$runner"; wait "$runner" 2>/dev/null || true
# The jobs die with their runner (the kernel signals them): wait for that state, bounded.
for _ in $(seq 1 600); do
  pgrep -f -- "--out $out/b" > /dev/null || break
  sleep 0.1
done
if pgrep -f -- "--out $out/b" > /dev/null; then fail "jobs outlived the killed runner by a minute"; fi
finished_before=$(finished_runs)
[ "$finished_before" -lt 8 ] || fail "all runs finished before the kill: nothing to resume"
sums_before=$(cd "$out/b" && find . -mindepth 2 -maxdepth 2 -name metrics.csv -path './run_*/*' ! -path '*.partial/*' -exec sha256sum {} + | sed 's| \./| |')
echo "killed with $finished_before of 8 runs finished"

"$batch" "${args[@]}" || fail "the resumed runner failed"
sums_after=$(cd "$out/b" && sha256sum run_*/metrics.csv)
while read -r line; do
  grep -qxF "$line" <<< "$sums_after" || fail "a finished run was changed: $line"
done <<< "$sums_before"
[ "$(ls "$out"/b/run_*/metrics.csv | wc -l)" -eq 8 ] || fail "not every seed finished"
! ls -d "$out"/b/*.partial > /dev/null 2>&1 || fail "partial runs left"
[ -s "$out/b/table1.md" ] || fail "no table1.md"
grep -q "| lidarseg |" "$out/b/table1.md" || fail "table1.md has no lidarseg row"
echo "RESUMED: 8 of 8 runs finished, $finished_before kept unchanged"
