#!/usr/bin/env bash
# lidarseg's single entry script. Each command installs what is missing (Debian packages),
# configures and builds incrementally, then runs.
#
#   ./run.sh main    segment the embedded real dataset and the bundled simulated one (made on
#                    first use, deterministically); print statistics per cascade level
#   ./run.sh test    build with AddressSanitizer + UBSan and run the whole suite (CTest)
#   ./run.sh bench   Release build, then the Google Benchmark timings (docs/performance.md)
#   ./run.sh real    lidarseg-odometry with MRPT ICP on every real log (../shared/datasets and
#                    MRPT's datasets): build/results/real/<log>/ and a table (docs/results.md)
#   ./run.sh deps    only install the Debian packages
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
JOBS="$(nproc 2>/dev/null || echo 2)"
DEFAULT_RAWLOG="/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog"
PACKAGES=(cmake g++ make pkg-config libmrpt-dev mrpt-common mrpt-apps libeigen3-dev
          libopencv-dev libnanoflann-dev googletest libgtest-dev libbenchmark-dev zlib1g-dev
          opencv-doc xvfb xauth xdotool chromium)

log() { echo "[run.sh] $*" >&2; }

install_deps() {
  local missing=()
  for p in "${PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  [ "${#missing[@]}" -eq 0 ] && return 0
  log "installing Debian packages: ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { log "need root or sudo to install: ${missing[*]}"; exit 1; }
    sudo="sudo"
  fi
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# configure_build <build dir> <cmake args...>
configure_build() {
  local dir="$1"; shift
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S "$ROOT" -B "$dir" "$@"
  fi
  cmake --build "$dir" --parallel "$JOBS"
}

build_release() {
  configure_build "$ROOT/build/release" -DCMAKE_BUILD_TYPE=Release \
    -DLIDARSEG_BUILD_TESTS=OFF -DLIDARSEG_BUILD_BENCHMARKS=ON
}

cmd="${1:-help}"
case "$cmd" in
  deps)
    install_deps
    ;;
  main)
    install_deps
    build_release
    bin="$ROOT/build/release/apps"
    "$bin/lidarseg-segment" --config "$ROOT/config/default.ini" "$DEFAULT_RAWLOG"
    # The bundled simulated dataset: the paper's maze run, seed 1 (datasets/README.md).
    sim="$ROOT/datasets/sim/maze_lms100_seed1"
    if [ ! -f "$sim.rawlog" ]; then
      log "generating the bundled simulated dataset $sim.rawlog"
      "$bin/lidarseg-simulate" --world "$ROOT/config/worlds/maze.world" \
        --trajectory "$ROOT/config/worlds/maze.traj" --sensor lms100 --seed 1 --out "$sim"
    fi
    echo
    "$bin/lidarseg-segment" --config "$ROOT/config/default.ini" "$sim.rawlog"
    ;;
  test)
    install_deps
    configure_build "$ROOT/build/test" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIDARSEG_SANITIZE=ON \
      -DLIDARSEG_BUILD_TESTS=ON -DLIDARSEG_BUILD_BENCHMARKS=ON
    export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
    export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
    ctest --test-dir "$ROOT/build/test" --output-on-failure --parallel "$JOBS" --timeout 600
    ;;
  real)
    install_deps
    build_release
    bin="$ROOT/build/release/apps"
    out="$ROOT/build/results/real"
    mkdir -p "$out"
    shared="$ROOT/../shared/datasets"
    logs=()
    [ -d "$shared/radish-corrected" ] && logs+=("$shared"/radish-corrected/*.log.gz)
    [ -f "$shared/intel-mrpt/intel.rawlog" ] && logs+=("$shared/intel-mrpt/intel.rawlog")
    logs+=("$DEFAULT_RAWLOG" "/usr/share/mrpt/datasets/localization_demo.rawlog")
    for f in "${logs[@]}"; do
      name="$(basename "$f")"; name="${name%%.*}"; name="${name// /_}"
      extra=()
      case "$f" in *.log.gz) extra=(--log-reference) ;; esac
      log "$name"
      "$bin/lidarseg-odometry" -q --baseline icp --use-odometry "${extra[@]}" --out "$out/$name" "$f" \
        > "$out/$name.txt" || { log "FAILED: $f"; exit 1; }
    done
    for f in "${logs[@]}"; do
      name="$(basename "$f")"; name="${name%%.*}"; name="${name// /_}"
      echo "### $name"; sed -n '/^| method/,$p' "$out/$name/results.md"; grep "^lidarseg status" "$out/$name.txt"; echo
    done
    ;;
  bench)
    install_deps
    build_release
    for b in bench_segmentation bench_matching bench_simulation bench_features bench_people; do
      "$ROOT/build/release/tests/benchmarks/$b" \
        --benchmark_repetitions=10 --benchmark_report_aggregates_only=true "${@:2}"
    done
    ;;
  *)
    sed -n '2,9p' "$0"
    [ "$cmd" = help ] || exit 2
    ;;
esac
