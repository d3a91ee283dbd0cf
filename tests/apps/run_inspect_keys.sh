#!/usr/bin/env bash
# lidarseg-inspect's window driven by the keyboard under a virtual X server: step three
# scans, raise the W-D threshold, save the parameters, quit. Passes when the app quits at
# scan 3 and the saved INI holds the raised threshold. Every key waits for the window's
# state (--trace prints each shown picture), never for a fixed time.
#   run_inspect_keys.sh <lidarseg-inspect> <log> <out dir>
set -euo pipefail
app="$1"; log="$2"; out="$3"
mkdir -p "$out"
rm -f "$out/keys.ini"
export GALLIUM_DRIVER=softpipe
xvfb-run -a -s "-screen 0 1280x1024x24" bash -s "$app" "$log" "$out" <<'INNER'
set -euo pipefail
app="$1"; log="$2"; out="$3"
"$app" "$log" --width 800 --height 600 --save "$out/keys.ini" --trace > "$out/keys.log" 2>&1 &
pid=$!
shown() { grep -c "^shown scan" "$out/keys.log" 2>/dev/null || true; }
# wait_for PATTERN: until the app's log has a line matching it (the app alive), at most ~10 min
wait_for() {
  for _ in $(seq 1 6000); do
    grep -q "$1" "$out/keys.log" 2>/dev/null && return 0
    kill -0 "$pid" 2>/dev/null || { echo "the app ended early:"; cat "$out/keys.log"; exit 1; }
    sleep 0.1
  done
  echo "the window never reached: $1"; cat "$out/keys.log"; exit 1
}
wait_for "^shown scan 0"
win=""
for _ in $(seq 1 6000); do
  win=$(xdotool search --name "lidarseg-inspect" 2>/dev/null | head -1) && [ -n "$win" ] && break
  sleep 0.1
done
[ -n "$win" ] || { echo "no window"; exit 1; }
# Focus the window (a click into it), then send each key once the previous one was shown.
xdotool mousemove 300 300 click 1
key() {  # key NAME EXPECTED_PATTERN
  local before; before=$(shown)
  for _ in $(seq 1 20); do  # a key pressed before the window had focus is sent again
    xdotool mousemove 300 300 click 1 key "$1"
    for _ in $(seq 1 300); do
      [ "$(shown)" -gt "$before" ] && break
      sleep 0.1
    done
    [ "$(shown)" -gt "$before" ] && break
  done
  wait_for "$2"
}
key n "^shown scan 1"
key n "^shown scan 2"
key n "^shown scan 3"
key bracketright "^shown scan 3 (.*W-D"
key s "parameters saved to"
xdotool key q
wait "$pid"
INNER
test -f "$out/keys.ini" || { echo "the 's' key saved nothing"; cat "$out/keys.log"; exit 1; }
grep -q "quit at scan 3" "$out/keys.log" || { echo "three 'n' did not step to scan 3:"; cat "$out/keys.log"; exit 1; }
value=$(sed -n 's/^wd_threshold_m *= *//p' "$out/keys.ini")
echo "saved wd_threshold_m = $value"
awk -v v="$value" 'BEGIN { exit !(v > 0.01979 && v < 0.01981) }' || { echo "expected 0.018 x 1.1 = 0.0198"; exit 1; }
