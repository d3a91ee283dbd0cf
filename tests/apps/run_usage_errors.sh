#!/bin/bash
# Issue 16: a wrong command line is a usage error (a message naming the option, exit 2),
# with nothing read, run or written: out-of-range values, unknown names, an output that is
# an input, two outputs on one path, an output folder that is a file.
# usage: run_usage_errors.sh APPS_DIR WORLDS_DIR WORK_DIR
set -u
bin=$1; worlds=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
cd "$work" || exit 1
fails=0
printf 'FLASER 3 1 1 1 0 0 0 0 0 0 1 h 1\n' > log.log
# check NAME STATUS STDERR_PATTERN TOOL ARGS...: the status, the message, and no "out" made.
check() {
  local name=$1 want=$2 pattern=$3; shift 3
  rm -rf out
  "$bin/$1" "${@:2}" > stdout.txt 2> stderr.txt < /dev/null
  local rc=$?
  if [ "$rc" != "$want" ]; then echo "FAIL $name: exit $rc, expected $want"; cat stderr.txt; fails=$((fails+1)); return; fi
  if ! grep -q -- "$pattern" stderr.txt stdout.txt; then
    echo "FAIL $name: no '$pattern' in:"; cat stderr.txt; fails=$((fails+1))
  fi
  if [ "$want" = 2 ] && [ -e out ]; then echo "FAIL $name: 'out' was made"; fails=$((fails+1)); fi
}
# Unsigned options given a negative or empty value (TCLAP read -1 as 2^64 - 1, '' as 0).
check "odometry -n -1" 2 "usage error: -n/--max-scans: '-1' is not a whole number" lidarseg-odometry log.log -n -1 -o out
check "odometry -n ''" 2 "usage error: -n/--max-scans: '' is not a whole number" lidarseg-odometry log.log -n '' -o out
check "features -n -1" 2 "usage error: -n/--max-scans" lidarseg-features log.log -n -1 -o out
check "segment -n -1" 2 "usage error: -n/--max-scans" lidarseg-segment log.log -n -1 -o out
check "odometry '-n -1' in one argument" 2 "usage error: -n/--max-scans: '-1' is not a whole number" lidarseg-odometry log.log '-n -1' -o out
check "people --every -1" 2 "usage error: --every: '-1'" lidarseg-people log.log --roi 0,0,9,9 --every -1 -o out
# An option that only means something with another, given without it (it was ignored).
check "features --gate without --gt" 2 "usage error: --gate needs --gt" lidarseg-features log.log --gate 0.3 -o out
check "people --draw-every -1" 2 "usage error: --draw-every" lidarseg-people log.log --roi 0,0,9,9 --draw-every -1 -o out
check "people -n -1" 2 "usage error: -n/--max-frames" lidarseg-people log.log --roi 0,0,9,9 -n -1 -o out
check "inspect -f -1" 2 "usage error: -f/--frame: '-1'" lidarseg-inspect log.log -f -1 --draw out.png
check "inspect --gallery -1" 2 "usage error: --gallery: '-1'" lidarseg-inspect log.log --gallery -1 -o out
check "simulate --camera-every -1" 2 "usage error: --camera-every" lidarseg-simulate -w "$worlds/maze.world" -t "$worlds/maze.traj" --camera-every -1 -o out/
check "simulate --seed -1" 2 "usage error: --seed" lidarseg-simulate -w "$worlds/maze.world" -t "$worlds/maze.traj" --seed -1 -o out/
# Values checked after parsing are usage errors too (they printed "error:").
printf '[segmentation]\n' > seg.ini
check "segment --section ''" 2 "usage error: --section: an empty name names no section" lidarseg-segment log.log -c seg.ini --section '' -o out
check "odometry --max-lost-ratio 2" 2 "usage error: --max-lost-ratio must be in \[0, 1\] (got 2)" lidarseg-odometry log.log --max-lost-ratio 2 -o out
check "odometry --baseline csm" 2 "usage error: --baseline 'csm' (known:" lidarseg-odometry log.log --baseline csm -o out
# The value as typed (it read "(got -2.000000)" for -1, "(got 0.000000)" for 1e-300).
check "odometry --scanner-hz -5" 2 "usage error: --scanner-hz must be 0 (no correction) or from 0.1 to 1000 Hz (got -5)" lidarseg-odometry log.log --scanner-hz -5 -o out
check "odometry --scanner-hz 1e-300" 2 "usage error: --scanner-hz must be 0 (no correction) or from 0.1 to 1000 Hz (got 1e-300)" lidarseg-odometry log.log --scanner-hz 1e-300 -o out
check "odometry --scanner-hz -1" 2 "usage error: --scanner-hz must be 0 (no correction) or from 0.1 to 1000 Hz (got -1)" lidarseg-odometry log.log --scanner-hz -1 -o out
# Unknown names and contradictory options: usage errors (they exited 1).
check "odometry --scan-stamp foo" 2 "usage error: --scan-stamp: scan stamp 'foo'" lidarseg-odometry log.log --scan-stamp foo -o out
check "simulate --scan-stamp foo" 2 "usage error: --scan-stamp" lidarseg-simulate -w "$worlds/maze.world" -t "$worlds/maze.traj" --scan-stamp foo -o out/
check "simulate --sensor-model LMS100" 2 "usage error: --sensor-model: unknown sensor profile 'LMS100'" lidarseg-simulate -w "$worlds/maze.world" -t "$worlds/maze.traj" --sensor-model LMS100 -o out/
check "simulate --building with -w" 2 "usage error: --building replaces" lidarseg-simulate --building 3 -w "$worlds/maze.world" -o out/
check "inspect --draw d.txt" 2 "usage error: --draw 'd.txt': the name must end in .png or .svg" lidarseg-inspect log.log --draw d.txt
check "features --gate -1" 2 "usage error: --gate must be a distance > 0 m (got -1)" lidarseg-features log.log --gt log.log --gate -1 -o out
check "batch --sensor-model LMS100" 2 "usage error: --sensor-model: unknown sensor profile 'LMS100'" lidarseg-batch run --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --seeds 1-2 --sensor-model LMS100 -o out
check "batch -j 100000" 2 "usage error: -j/--jobs must be in \[1, 256\]" lidarseg-batch run --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --seeds 1-2 -j 100000 -o out
check "batch -j -1" 2 "usage error: -j/--jobs: '-1'" lidarseg-batch run --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --seeds 1-2 -j -1 -o out
check "batch --version" 0 "version: 0.1.0" lidarseg-batch --version
# A flag of the other sub-command, or one that contradicts another or acts on nothing, is a
# usage error (run --seed 7 ran seeds 1-50; the others were ignored without a word).
check "batch run --seed" 2 "usage error: --seed is not an option of 'run'" lidarseg-batch run --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --seed 7 -o out
check "batch one --seeds" 2 "usage error: --seeds is not an option of 'one'" lidarseg-batch one --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --seeds 3-4 -o out
check "batch one -j" 2 "usage error: -j/--jobs is not an option of 'one'" lidarseg-batch one --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" -j 5 -o out
check "batch one --title" 2 "usage error: --title is not an option of 'one'" lidarseg-batch one --world "$worlds/maze.world" --trajectory "$worlds/maze.traj" --title t -o out
check "odometry --gt with --no-gt" 2 "usage error: --gt log.log and --no-gt contradict" lidarseg-odometry log.log --gt log.log --no-gt -o out
check "odometry --relations-tolerance alone" 2 "usage error: --relations-tolerance applies to the relations of --relations" lidarseg-odometry log.log --relations-tolerance 0.1 -o out
check "odometry --scan-stamp without the correction" 2 "usage error: --scan-stamp last places the beams for the rolling-shutter correction, which is off" lidarseg-odometry log.log --scan-stamp last -o out
# An output that is an input, and two outputs on one path.
mkdir -p oz io
cp log.log oz/timing.csv; cp log.log io/index.html; cp log.log oz/lidarseg.tum
check "odometry input in -o" 2 "usage error: -o 'oz/timing.csv' is the input 'oz/timing.csv'" lidarseg-odometry oz/timing.csv -q -o oz
check "odometry --gt in -o" 2 "is the input 'oz/lidarseg.tum'" lidarseg-odometry log.log -q -o oz --gt oz/lidarseg.tum
check "inspect input in -o" 2 "usage error: -o 'io/index.html' is the input" lidarseg-inspect io/index.html -o io
mkdir -p ob; cp "$worlds/maze.traj" ob/table1.md
check "batch input in --out" 2 "usage error: --out 'ob/table1.md' is the input 'ob/table1.md'" lidarseg-batch run --world "$worlds/maze.world" --trajectory ob/table1.md --seeds 1 -o ob
cmp -s "$worlds/maze.traj" ob/table1.md || { echo "FAIL: batch: an input was changed"; fails=$((fails+1)); }
cmp -s log.log oz/timing.csv && cmp -s log.log io/index.html && cmp -s log.log oz/lidarseg.tum || { echo "FAIL: an input was changed"; fails=$((fails+1)); }
check "odometry two outputs" 2 "usage error: --write-rawlog 'X' and --features-out 'X'" lidarseg-odometry log.log -o out --features-out X --write-rawlog X
check "odometry rawlog on summary" 2 "--write-rawlog 'out/summary.json' and -o" lidarseg-odometry log.log -o out --write-rawlog out/summary.json
check "odometry features-out on -o" 2 "--features-out 'out' and -o" lidarseg-odometry log.log -o out --features-out out
check "features rois on csv" 2 "--out 'out/features.csv' and --rois-out" lidarseg-features log.log -o out --rois-out out/features.csv
check "features rois on figure" 2 "--rois-out 'Y' and --figure 'Y'" lidarseg-features log.log -o out --rois-out Y --figure Y
check "features rois on matches" 2 "--rois-out 'X' and --matches-out 'X'" lidarseg-features log.log --gt log.log -o out --rois-out X --matches-out X
check "features images on csv" 2 "--images-out 'out/features.csv'" lidarseg-features log.log -o out --images-out out/features.csv
check "people draw on csv" 2 "--out 'out/people.csv' and --draw" lidarseg-people log.log -o out --roi 0,0,300,300 --draw out/people.csv
[ -e X ] || [ -e Y ] && { echo "FAIL: X or Y written"; fails=$((fails+1)); }
# An output folder that is a file, or under one: the reason, not the lock's.
check "-o a file" 2 "usage error: -o 'log.log': an output folder, but a file of that name exists" lidarseg-odometry oz/timing.csv -o log.log
check "-o under a file" 1 "cannot create the output folder 'log.log/x': Not a directory" lidarseg-segment oz/timing.csv -o log.log/x
# Two options naming one output: one of them was silently not written, exit 0 (issue 16).
check "segment -o with --csv" 2 "usage error: -o/--out and --csv (its old form) both say where segments.csv goes; give one" lidarseg-segment log.log -o out --csv other.csv
check "inspect -o with --report" 2 "usage error: -o/--out and --report (its old form) both name the report folder; give one" lidarseg-inspect log.log -o out --report other
check "inspect -o X.png with --draw" 2 "usage error: -o out.png (its old form) and --draw both name the picture; give one" lidarseg-inspect log.log -o out.png --draw other.png
check "features -o with -r" 2 "usage error: -o/--out DIR and -r/--report (its old form) both name the folder of features.md; give one" lidarseg-features log.log -o out -r other
check "people -o with -r" 2 "usage error: -o/--out DIR and -r/--report (its old form) both name the folder of people.md; give one" lidarseg-people log.log --roi 0,0,9,9 -o out -r other
for f in other.csv other other.png; do [ -e "$f" ] && { echo "FAIL: $f was made"; fails=$((fails+1)); }; done
# The same folder named by both (another spelling included) is one output, not a conflict:
# the run goes on past the command line (people: to its missing input's error; a log that
# is no image would have OpenCV probe its video backends, whose libusb leaks under LSan).
check "features -o X -r X/" 0 "" lidarseg-features -q log.log -o out -r out/
[ -f out/features.md ] && [ -f out/features.csv ] || { echo "FAIL features -o X -r X/: out/features.md or .csv missing"; fails=$((fails+1)); }
check "inspect -o X --report X/." 0 "" lidarseg-inspect -q log.log -o out --report out/.
[ -f out/index.html ] || { echo "FAIL inspect -o X --report X/.: out/index.html missing"; fails=$((fails+1)); }
check "people -o X -r ./X" 1 "lidarseg-people: error: 'missing.png': no such file" lidarseg-people missing.png --roi 0,0,9,9 -o out -r ./out
# Two options choosing the scan (one was silently ignored); a time past the log's end.
check "inspect --time with -f" 2 "usage error: -f/--frame, --render and --time each choose the scan; give one" lidarseg-inspect log.log --draw out.png --time 1 -f 5
check "inspect --time with --render" 2 "usage error: -f/--frame, --render and --time" lidarseg-inspect log.log --draw out.png --time 1 --render 2
check "inspect --time past the end" 1 "error: --time 1e+300 s: past the end of 'log.log', whose last scan is at 0 s from its first" lidarseg-inspect log.log --draw out.png --time 1e300 -q
check "inspect --time negative" 1 "error: --time -2 s: times count from the log's first scan" lidarseg-inspect log.log --draw out.png --time -2 -q
# An output file that is a FIFO (a device, as root) would be replaced by the publish.
mkfifo fifo.csv
check "segment --csv FIFO" 2 "usage error: --csv 'fifo.csv': an output file, but a device, FIFO or socket" lidarseg-segment log.log --csv fifo.csv
[ -p fifo.csv ] || { echo "FAIL segment --csv FIFO: the FIFO was replaced"; fails=$((fails+1)); }
# A report that cannot be written to stdout (a full disk) is the run's error, not a success.
for tool in lidarseg-segment lidarseg-features; do
  "$bin/$tool" -q log.log > /dev/full 2> stderr.txt < /dev/null
  rc=$?
  if [ "$rc" != 1 ] || ! grep -q "$tool: error: cannot write the report to standard output" stderr.txt; then
    echo "FAIL $tool > /dev/full: exit $rc"; cat stderr.txt; fails=$((fails+1))
  fi
done
[ "$fails" = 0 ] && echo "every wrong command line is a usage error" || exit 1
