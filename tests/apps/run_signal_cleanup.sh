#!/bin/bash
# SIGTERM during a run leaves no temporary file and no partial output (issue 16), and a
# second run into the same folder while the first holds it is refused.
# usage: run_signal_cleanup.sh ODOMETRY_BIN LOG TMPDIR
set -u
bin=$1; log=$2; tmp=$3
rm -rf "$tmp"; mkdir -p "$tmp"
"$bin" -q --no-plots --baseline icp,icp-s2s -o "$tmp/out" --write-rawlog "$tmp/out/back.rawlog" "$log" \
  >"$tmp/first.txt" 2>&1 &
pid=$!
# Wait for the state "the run has started writing" (its temporary rawlog exists).
for _ in $(seq 1 6000); do
  compgen -G "$tmp/out/back.rawlog.tmp.*" >/dev/null && break
  kill -0 $pid 2>/dev/null || break
  sleep 0.05
done
if ! compgen -G "$tmp/out/back.rawlog.tmp.*" >/dev/null; then
  echo "FAIL: the run never wrote its temporary rawlog"; cat "$tmp/first.txt"; exit 1
fi
# A second writer into the same folder is refused while the first runs.
"$bin" -q --no-plots -o "$tmp/out" "$log" >"$tmp/second.txt" 2>&1
rc2=$?
kill -TERM $pid
wait $pid
rc=$?
fails=0
if [ "$rc2" = 0 ] || ! grep -q "another run is writing into" "$tmp/second.txt"; then
  echo "FAIL: a second writer was not refused (exit $rc2)"; cat "$tmp/second.txt"; fails=1
fi
if [ "$rc" != 143 ]; then echo "FAIL: exit $rc after SIGTERM, expected 143"; fails=1; fi
left=$(find "$tmp/out" -name '*.tmp*' 2>/dev/null)
if [ -n "$left" ]; then echo "FAIL: temporary files left: $left"; fails=1; fi
for f in summary.json lidarseg.tum back.rawlog; do
  [ -e "$tmp/out/$f" ] && { echo "FAIL: a partial run published $f"; fails=1; }
done
# The folder the run made for its outputs goes too (it was left with its lock file).
[ -e "$tmp/out" ] && { echo "FAIL: the output folder the run made was left: $(ls -A "$tmp/out")"; fails=1; }
# SIGHUP (a closed terminal) and SIGQUIT clean up the same way (they left the temporary
# rawlog). env --default-signal: the test holds even when ctest runs under nohup.
for sig in HUP:129 QUIT:131; do
  name=${sig%%:*}; expected=${sig##*:}
  rm -rf "$tmp/$name"
  env --default-signal="$name" "$bin" -q --no-plots -o "$tmp/$name" --write-rawlog "$tmp/$name/w.rawlog" "$log" \
    >"$tmp/$name.txt" 2>&1 &
  pid=$!
  for _ in $(seq 1 6000); do
    compgen -G "$tmp/$name/w.rawlog.tmp.*" >/dev/null && break
    kill -0 $pid 2>/dev/null || break
    sleep 0.05
  done
  if ! compgen -G "$tmp/$name/w.rawlog.tmp.*" >/dev/null; then
    echo "FAIL: SIG$name: the run never wrote its temporary rawlog"; cat "$tmp/$name.txt"; exit 1
  fi
  kill -"$name" $pid
  wait $pid
  rc=$?
  if [ "$rc" != "$expected" ]; then echo "FAIL: exit $rc after SIG$name, expected $expected"; fails=1; fi
  left=$(find "$tmp/$name" -name '*.tmp*' 2>/dev/null)
  if [ -n "$left" ]; then echo "FAIL: temporary files left after SIG$name: $left"; fails=1; fi
  [ -e "$tmp/$name/w.rawlog" ] && { echo "FAIL: SIG$name: a partial run published w.rawlog"; fails=1; }
  [ -e "$tmp/$name" ] && { echo "FAIL: SIG$name: the output folder the run made was left: $(ls -A "$tmp/$name")"; fails=1; }
done
[ $fails = 0 ] && echo "signal cleanup and folder lock hold"
exit $fails
