#!/usr/bin/env bash
# MRPT's own apps on a rawlog written by lidarseg-odometry, with the project's configs:
# icp-slam builds a map with lidarseg as its odometry, pf-localization tracks the robot in
# that map. Checks: icp-slam finds no empty point map and ends near lidarseg's last pose;
# the particle filter ends near icp-slam's pose; and lidarseg's motion covariance keeps the
# adaptive filter smaller than the log's own wheel odometry does (the median particle count
# over the run, same map, same filter settings).
# usage: run_mrpt_slam_localization.sh LIDARSEG_ODOMETRY CONFIG_DIR TELECOM.rawlog WORK_DIR
set -euo pipefail
odometry="$1"; config="$2"; input="$3"; work="$4"
rm -rf "$work"; mkdir -p "$work/wheel"
cd "$work"
fail() { echo "FAIL: $*"; exit 1; }

"$odometry" -q --no-plots -o odometry --write-rawlog lidarseg.rawlog "$input" > odometry.txt
icp-slam "$config/icp-slam/lidarseg-odometry.ini" lidarseg.rawlog < /dev/null > icp-slam.txt 2>&1 ||
  fail "icp-slam exited $? (icp-slam.txt)"
[ -s icp-slam/_finalmap_.simplemap ] || fail "icp-slam wrote no map"
! grep -q "Cannot do ICP" icp-slam.txt || fail "icp-slam: $(grep -c 'Cannot do ICP' icp-slam.txt) x 'Cannot do ICP'"

# distance X1 Y1 X2 Y2
distance() { awk -v a="$1" -v b="$2" -v c="$3" -v d="$4" 'BEGIN { printf "%.3f", sqrt((a-c)^2 + (b-d)^2) }'; }
read -r _ sx sy _ < <(tail -n 1 icp-slam/log_estimated_path.txt)
read -r _ lx ly _ < <(tail -n 1 odometry/lidarseg.tum)
d=$(distance "$sx" "$sy" "$lx" "$ly")
echo "icp-slam ends at ($sx, $sy), lidarseg at ($lx, $ly): $d m apart"
awk -v d="$d" 'BEGIN { exit !(d < 0.5) }' || fail "icp-slam and lidarseg end $d m apart"

# pf_run RAWLOG FOLDER: runs the filter in FOLDER (which sees ./icp-slam), prints
# "median_particles x y" of the run.
pf_run() {
  (cd "$2" && [ -e icp-slam ] || ln -s "$work/icp-slam" "$2/icp-slam"
   cd "$2" && pf-localization "$config/pf-localization/lidarseg-odometry.ini" "$1" < /dev/null > pf.txt 2>&1 ||
     fail "pf-localization exited $? on $1 ($2/pf.txt)")
  local stats=("$2"/pf-localization_000_*/PF_stats.txt)
  [ -s "${stats[0]}" ] || fail "pf-localization wrote no PF_stats.txt in $2"
  local median
  median=$(awk '{ print $1 }' "${stats[0]}" | sort -n | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }')
  local last
  last=$(grep 'PDF estimation' "$2/pf.txt" | tail -n 1 | sed -E 's/.*estimation: \(([^,]+),([^,]+),.*/\1 \2/')
  echo "$median $last"
}
read -r n_lidarseg px py < <(pf_run "$work/lidarseg.rawlog" "$work")
read -r n_wheel _ _ < <(pf_run "$input" "$work/wheel")
d=$(distance "$px" "$py" "$sx" "$sy")
echo "pf-localization ends at ($px, $py), $d m from icp-slam; median particles: $n_lidarseg with lidarseg, $n_wheel with wheel odometry"
awk -v d="$d" 'BEGIN { exit !(d < 0.3) }' || fail "the particle filter ends $d m from icp-slam's pose"
[ "$n_lidarseg" -lt "$n_wheel" ] || fail "lidarseg's motion needs $n_lidarseg particles, wheel odometry $n_wheel"
echo "PASS: MRPT icp-slam and pf-localization on lidarseg's rawlog"
