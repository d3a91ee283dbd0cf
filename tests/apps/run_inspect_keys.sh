#!/usr/bin/env bash
# lidarseg-inspect's window driven by the keyboard under a virtual X server: step three
# scans, raise the W-D threshold, save the parameters, quit. Passes when the app quits at
# scan 3 and the saved INI holds the raised threshold.
#   run_inspect_keys.sh <lidarseg-inspect> <log> <out dir>
set -euo pipefail
app="$1"; log="$2"; out="$3"
mkdir -p "$out"
rm -f "$out/keys.ini"
export GALLIUM_DRIVER=softpipe
xvfb-run -a -s "-screen 0 1280x1024x24" bash -s "$app" "$log" "$out" <<'INNER'
set -euo pipefail
app="$1"; log="$2"; out="$3"
"$app" "$log" --width 800 --height 600 --save "$out/keys.ini" > "$out/keys.log" 2>&1 &
pid=$!
for _ in $(seq 1 100); do
  xdotool search --name "lidarseg-inspect" > /dev/null 2>&1 && break
  sleep 0.1
done
sleep 1
xdotool mousemove 300 300 click 1
for k in n n n bracketright s; do xdotool key "$k"; sleep 0.3; done
for _ in $(seq 1 50); do [ -f "$out/keys.ini" ] && break; sleep 0.1; done
xdotool key q
wait "$pid"
INNER
test -f "$out/keys.ini" || { echo "the 's' key saved nothing"; cat "$out/keys.log"; exit 1; }
grep -q "quit at scan 3" "$out/keys.log" || { echo "three 'n' did not step to scan 3:"; cat "$out/keys.log"; exit 1; }
value=$(sed -n 's/^wd_threshold_m *= *//p' "$out/keys.ini")
echo "saved wd_threshold_m = $value"
awk -v v="$value" 'BEGIN { exit !(v > 0.01979 && v < 0.01981) }' || { echo "expected 0.018 x 1.1 = 0.0198"; exit 1; }
