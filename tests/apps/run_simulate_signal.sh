#!/bin/bash
# SIGINT during lidarseg-simulate leaves no temporary file or folder and publishes nothing
# (issue 16); so does SIGTERM while its camera images are written.
# The run is made long (a 1 kHz scanner, the largest rate accepted, over the maze loop) so that it is still writing when
# the signal comes; the test waits for the state "writing" (a temporary exists), not a time.
# usage: run_simulate_signal.sh SIMULATE_BIN WORLDS_DIR TMPDIR
set -u
bin=$1; worlds=$2; tmp=$3
rm -rf "$tmp"; mkdir -p "$tmp"
printf '[simulation]\nfrequency_hz = 1000\n' > "$tmp/fast.ini"
fails=0

# interrupt NAME CAMERA_EVERY WRITING_GLOB SIGNAL EXIT PUBLISHED...: runs the simulator into
# $tmp/NAME, sends SIGNAL once a file matches $tmp/NAME/WRITING_GLOB, then checks the exit
# code, that nothing named *.tmp* is left and that none of PUBLISHED exists.
interrupt() {
  local name=$1 camera=$2 writing=$3 sig=$4 expected=$5; shift 5
  env --default-signal="$sig" "$bin" -q -c "$tmp/fast.ini" --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" \
    --camera-every "$camera" -o "$tmp/$name/" >"$tmp/$name.txt" 2>&1 &
  local pid=$!
  for _ in $(seq 1 6000); do
    compgen -G "$tmp/$name/$writing" >/dev/null && break
    kill -0 $pid 2>/dev/null || break
    sleep 0.05
  done
  if ! compgen -G "$tmp/$name/$writing" >/dev/null; then
    echo "FAIL: $name: the run never wrote $writing"; cat "$tmp/$name.txt"; exit 1
  fi
  kill -"$sig" $pid
  wait $pid
  local rc=$?
  if [ "$rc" != "$expected" ]; then
    echo "FAIL: $name: exit $rc after SIG$sig, expected $expected"; cat "$tmp/$name.txt"; fails=1
  fi
  local left
  left=$(find "$tmp/$name" -name '*.tmp*')
  if [ -n "$left" ]; then echo "FAIL: $name: temporaries left: $(echo $left | head -c 300)"; fails=1; fi
  for f in "$@"; do
    [ -e "$tmp/$name/$f" ] && { echo "FAIL: $name: an interrupted run published $f"; fails=1; }
  done
}

interrupt out 0 '*.tmp.*' INT 130 maze.rawlog maze.gt.tum maze.features.csv
# With a camera, PREFIX_Images.tmp/ and the images in it go too (a registered temporary
# folder), and no PREFIX_Images/ is published.
interrupt cam 5 'maze_Images.tmp/img_*.png' TERM 143 maze.rawlog maze_Images
# SIGHUP (a closed terminal) left the temporaries and PREFIX_Images.tmp/ (issue 16).
interrupt hup 5 'maze_Images.tmp/img_*.png' HUP 129 maze.rawlog maze_Images
[ $fails = 0 ] && echo "simulate: interrupted cleanly"
exit $fails
