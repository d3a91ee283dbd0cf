#!/bin/bash
# -o names an output folder in every tool (docs/cli.md): each tool writes its files there.
# usage: run_out_folders.sh APPS_DIR WORLDS_DIR TELECOM.rawlog WORK_DIR
set -u
bin=$1; worlds=$2; log=$3; work=$4
rm -rf "$work"; mkdir -p "$work"
fails=0
expect() {  # expect FILE...
  for f in "$@"; do [ -s "$f" ] || { echo "FAIL: $f missing"; fails=$((fails+1)); }; done
}
run() { "$@" > "$work/last.txt" 2>&1 || { echo "FAIL: $* exited $?"; cat "$work/last.txt"; fails=$((fails+1)); }; }
run "$bin/lidarseg-simulate" -q --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --camera-every 0 -o "$work/sim/"
expect "$work/sim/maze.rawlog" "$work/sim/maze.gt.tum" "$work/sim/maze.features.csv"
run "$bin/lidarseg-features" -q -n 50 -o "$work/features" "$log"
expect "$work/features/features.csv" "$work/features/features.md" "$work/features/features.json"
run "$bin/lidarseg-segment" -q -n 50 -o "$work/segment" "$log"
expect "$work/segment/segments.csv"
run "$bin/lidarseg-odometry" -q --no-plots -n 50 -o "$work/odometry" "$log"
expect "$work/odometry/lidarseg.tum" "$work/odometry/summary.json"
run "$bin/lidarseg-inspect" -q --gallery 2 -o "$work/inspect" "$log"
expect "$work/inspect/index.html"
# The older file form of -o still writes the one file, with a note.
run "$bin/lidarseg-features" -q -n 20 -o "$work/old.csv" "$log"
expect "$work/old.csv"
grep -q "note: -o" "$work/last.txt" || { echo "FAIL: no note for -o FILE.csv"; fails=$((fails+1)); }
[ "$fails" = 0 ] && echo "every tool writes into its -o folder" || exit 1
