#!/bin/bash
# SIGINT during lidarseg-simulate leaves no temporary file and publishes nothing (issue 16).
# The run is made long (a 2 kHz scanner over the maze loop) so that it is still writing when
# the signal comes; the test waits for the state "writing" (a temporary exists), not a time.
# usage: run_simulate_signal.sh SIMULATE_BIN WORLDS_DIR TMPDIR
set -u
bin=$1; worlds=$2; tmp=$3
rm -rf "$tmp"; mkdir -p "$tmp"
printf '[simulation]\nfrequency_hz = 2000\n' > "$tmp/fast.ini"
"$bin" -q -c "$tmp/fast.ini" --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --camera-every 0 \
  -o "$tmp/out/" >"$tmp/run.txt" 2>&1 &
pid=$!
for _ in $(seq 1 6000); do
  compgen -G "$tmp/out/*.tmp.*" >/dev/null && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.05
done
if ! compgen -G "$tmp/out/*.tmp.*" >/dev/null; then
  echo "FAIL: the run never wrote a temporary file"; cat "$tmp/run.txt"; exit 1
fi
kill -INT $pid
wait $pid
rc=$?
fails=0
if [ "$rc" != 130 ]; then echo "FAIL: exit $rc after SIGINT, expected 130"; cat "$tmp/run.txt"; fails=1; fi
left=$(find "$tmp/out" -name '*.tmp*')
if [ -n "$left" ]; then echo "FAIL: temporary files left: $left"; fails=1; fi
for f in maze.rawlog maze.gt.tum maze.features.csv; do
  [ -e "$tmp/out/$f" ] && { echo "FAIL: an interrupted run published $f"; fails=1; }
done
[ $fails = 0 ] && echo "simulate: interrupted cleanly"
exit $fails
