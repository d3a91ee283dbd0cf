#!/bin/bash
# SIGTERM while gnuplot draws a figure leaves no scratch folder behind in TMPDIR (the plots'
# lidarseg-plot.* folders are registered with the signal cleanup). A stand-in `gnuplot`
# first on PATH stops its parent with SIGTERM: the state "a figure is being drawn" is reached
# deterministically, with no timing.
# usage: run_plot_signal.sh ODOMETRY_BIN LOG TMPDIR
set -u
bin=$1; log=$2; tmp=$3
rm -rf "$tmp"; mkdir -p "$tmp/bin" "$tmp/scratch"
cat > "$tmp/bin/gnuplot" <<'SH'
#!/bin/bash
ls "$TMPDIR" > "$TMPDIR/../seen.txt"
kill -TERM $PPID
SH
chmod +x "$tmp/bin/gnuplot"
PATH="$tmp/bin:$PATH" TMPDIR="$tmp/scratch" "$bin" -q -o "$tmp/out" "$log" >"$tmp/run.txt" 2>&1
rc=$?
fails=0
if [ "$rc" != 143 ]; then echo "FAIL: exit $rc, expected 143 (SIGTERM while plotting)"; cat "$tmp/run.txt"; fails=1; fi
if ! grep -q '^lidarseg-plot\.' "$tmp/seen.txt" 2>/dev/null; then
  echo "FAIL: the stand-in gnuplot saw no scratch folder"; fails=1
fi
left=$(ls -A "$tmp/scratch")
if [ -n "$left" ]; then echo "FAIL: left in TMPDIR: $left"; fails=1; fi
[ $fails = 0 ] && echo "no plot scratch folder left after SIGTERM"
exit $fails
