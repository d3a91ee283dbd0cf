#!/bin/bash
# Issue 16: a folder a tool replaces as its own (lidarseg-simulate's PREFIX_Images/,
# lidarseg-batch's unfinished run_<seed>/) that holds files the tool did not write (the
# user's, or the run's own inputs) is refused with the file named, and nothing in it is
# removed; an earlier run's images are still replaced.
# usage: run_foreign_folders.sh APPS_DIR WORLDS_DIR WORK_DIR
set -u
bin=$1; worlds=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
cd "$work" || exit 1
fails=0
fail() { echo "FAIL $*"; fails=$((fails+1)); }
printf 'speed 1\nwaypoint 0.5 0.5\nwaypoint 2.5 0.5\n' > short.traj
# Simulate: the world, the trajectory and a note of the user's inside out/maze_Images/.
mkdir -p out/maze_Images
cp "$worlds/maze.world" out/maze_Images/
cp short.traj out/maze_Images/
echo precious > out/maze_Images/notes.txt
"$bin/lidarseg-simulate" -q -w out/maze_Images/maze.world -t out/maze_Images/short.traj -o out/maze --camera-every 25 \
  > sim.txt 2>&1
rc=$?
[ "$rc" = 1 ] || fail "simulate into a user's _Images folder: exit $rc, expected 1"
grep -q "lidarseg-simulate: error: 'out/maze_Images' would be replaced by this run's camera images, but it holds 'out/maze_Images/" sim.txt \
  || { fail "simulate: no error naming the folder and its file:"; cat sim.txt; }
for f in maze.world short.traj notes.txt; do [ -s "out/maze_Images/$f" ] || fail "simulate removed out/maze_Images/$f"; done
# An earlier run's images (and only images) are replaced by the next run's.
"$bin/lidarseg-simulate" -q -w "$worlds/maze.world" -t short.traj -o sim2/maze --camera-every 25 > /dev/null 2>&1 || fail "simulate with images"
before=$(ls sim2/maze_Images | wc -l)
[ "$before" -gt 0 ] || fail "simulate wrote no image"
"$bin/lidarseg-simulate" -q -w "$worlds/maze.world" -t short.traj -o sim2/maze --camera-every 50 > /dev/null 2>&1 || fail "simulate again"
after=$(ls sim2/maze_Images | wc -l)
[ "$after" -gt 0 ] && [ "$after" -lt "$before" ] || fail "an earlier run's images not replaced ($before then $after)"
# Batch: an unfinished run folder holding the user's files and the job's inputs.
mkdir -p b/run_1
cp "$worlds/maze.world" b/run_1/
cp short.traj b/run_1/t.traj
echo precious > b/run_1/notes.txt
"$bin/lidarseg-batch" run --world b/run_1/maze.world --trajectory b/run_1/t.traj -o b --seeds 1 -j 1 --no-icp -q > batch.txt 2>&1
rc=$?
[ "$rc" != 0 ] || fail "batch over a user's run_1: exit 0"
for f in maze.world t.traj notes.txt; do [ -s "b/run_1/$f" ] || fail "batch removed b/run_1/$f"; done
grep -q "is not a finished run (no metrics.csv) and holds 'b/run_1/" batch.txt b/run_1.log 2>/dev/null \
  || { fail "batch: no error naming the folder:"; cat batch.txt; }
[ "$fails" = 0 ] && echo "no folder of the user's is removed" || exit 1
