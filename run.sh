#!/usr/bin/env bash
# lidarseg's single entry script. Each command installs what is missing (Debian packages),
# configures and builds incrementally, then runs.
#
#   ./run.sh main    lidarseg against MRPT ICP (keyframed and scan to scan) on MRPT's real
#                    Telecom log, the bundled simulated maze (made on first use) and, when
#                    ../shared/datasets is there, two real Radish logs: time, speed-up,
#                    accuracy, lost scans, in one screen (reports in build/main/)
#   ./run.sh test    build with AddressSanitizer + UBSan and run the whole suite (CTest)
#   ./run.sh bench   Release build, then the Google Benchmark timings (docs/performance.md)
#   ./run.sh fuzz [SECONDS]  build the libFuzzer targets with clang (ASan + UBSan) and run each
#                    for SECONDS (default 60) from its committed seed corpus (docs/reliability.md)
#   ./run.sh tsan    ThreadSanitizer build; the batch runner's tests and apps under it
#   ./run.sh shared  shared-library build, installed and used by a separate project (CMake
#                    package and pkg-config)
#   ./run.sh real    lidarseg-odometry with MRPT ICP (keyframed and scan to scan) on every real
#                    log (../shared/datasets and MRPT's datasets): build/results/real/ and the
#                    table of docs/results.md
#   ./run.sh latency time per scan (median, p99, max) of lidarseg on every log, real and
#                    simulated, with the default configuration (docs/performance.md)
#   ./run.sh buildings [tune|evaluate]  doors and corners on generated buildings (issue 18):
#                    tune = seeds 1-20 only, evaluate = the held-out seeds 101-150 (default),
#                    LMS100 and UTM-30LX; build/results/buildings_<mode>/report.md
#   ./run.sh deps    only install the Debian packages
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
JOBS="$(nproc 2>/dev/null || echo 2)"
DEFAULT_RAWLOG="/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog"
PACKAGES=(cmake g++ make pkg-config python3 libmrpt-dev mrpt-common mrpt-apps libeigen3-dev
          libopencv-dev libnanoflann-dev gnuplot-nox googletest libgtest-dev libbenchmark-dev zlib1g-dev nlohmann-json3-dev
          opencv-doc xvfb xauth xdotool chromium clang libclang-rt-14-dev)
FUZZ_TARGETS=(fuzz_carmen_log fuzz_rawlog fuzz_sim_inputs fuzz_config fuzz_tables fuzz_scan_pipeline fuzz_command_line)

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
    # The bundled simulated dataset: the paper's maze run, seed 1 (datasets/README.md).
    sim="$ROOT/datasets/sim/maze_lms100_seed1"
    if [ ! -f "$sim.rawlog" ]; then
      log "generating the bundled simulated dataset $sim.rawlog"
      "$bin/lidarseg-simulate" --world "$ROOT/config/worlds/maze.world" \
        --trajectory "$ROOT/config/worlds/maze.traj" --sensor-model lms100 --seed 1 --out "$sim" >/dev/null
    fi
    # MRPT's real Telecom log, the simulated maze with its ground truth and, when
    # ../shared/datasets is there, two real CARMEN logs against their corrected poses.
    logs=("--log" "telecom (real, MRPT)=$DEFAULT_RAWLOG,--use-odometry"
          "--log" "maze (simulated)=$sim.rawlog,--gt,$sim.gt.tum,--use-odometry")
    radish="$ROOT/../shared/datasets/radish-corrected"
    for site in aces intel; do
      if [ -f "$radish/$site-corrected.log.gz" ]; then
        logs+=("--log" "$site (real, Radish)=$radish/$site-corrected.log.gz,--use-odometry,--log-reference")
      fi
    done
    python3 "$ROOT/tests/benchmarks/compare_with_icp.py" --bin "$bin" --config "$ROOT/config/default.ini" \
      --out "$ROOT/build/main" "${logs[@]}"
    ;;
  test)
    install_deps
    configure_build "$ROOT/build/test" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIDARSEG_SANITIZE=ON \
      -DLIDARSEG_BUILD_TESTS=ON -DLIDARSEG_BUILD_BENCHMARKS=ON
    export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
    export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$ROOT/tests/sanitizers/lsan.supp}"
    export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
    ctest --test-dir "$ROOT/build/test" --output-on-failure --parallel "$JOBS" --timeout 600
    ;;
  fuzz)
    install_deps
    seconds="${2:-60}"
    CXX=clang++ CC=clang configure_build "$ROOT/build/fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DLIDARSEG_FUZZ=ON -DLIDARSEG_BUILD_APPS=OFF -DLIDARSEG_BUILD_TESTS=OFF -DLIDARSEG_BUILD_BENCHMARKS=OFF
    work="$ROOT/build/fuzz/run"
    mkdir -p "$work/crashes"  # kept between local runs; CI starts from a fresh clone
    # Seeds: the committed corpus, plus the project's own configuration and world files
    # (prefixed with the byte that selects their format in the target).
    seeds="$work/project-seeds"; mkdir -p "$seeds/fuzz_config" "$seeds/fuzz_sim_inputs"
    for f in "$ROOT"/config/*.ini "$ROOT"/config/*/*.ini; do
      { printf '\x00'; cat "$f"; } > "$seeds/fuzz_config/$(basename "$f")"
    done
    for f in "$ROOT"/config/worlds/*.world; do { printf '\x00'; cat "$f"; } > "$seeds/fuzz_sim_inputs/$(basename "$f")"; done
    for f in "$ROOT"/config/worlds/*.traj; do { printf '\x01'; cat "$f"; } > "$seeds/fuzz_sim_inputs/$(basename "$f")"; done
    export ASAN_OPTIONS="detect_leaks=1"
    export LSAN_OPTIONS="suppressions=$ROOT/tests/sanitizers/lsan.supp"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    failed=()
    for t in "${FUZZ_TARGETS[@]}"; do
      corpus="$work/corpus/$t"; mkdir -p "$corpus"
      extra=()
      [ -d "$seeds/$t" ] && extra+=("$seeds/$t")
      # MRPT's deserialiser sizes containers from counts read in the file (D1 in
      # docs/reliability.md): even a cut rawlog can make it allocate gigabytes, which lidarseg
      # cannot intercept. The rawlog target therefore runs in fork mode with out-of-memory
      # inputs ignored (fork mode still exits non-zero after one, so only its crash, leak and
      # timeout artifacts fail the run).
      [ "$t" = fuzz_rawlog ] && extra+=(-fork=1 -ignore_ooms=1)
      log "$t: ${seconds} s"
      # -rss_limit_mb / -malloc_limit_mb: an input that makes a reader ask for gigabytes is a finding.
      bin="$ROOT/build/fuzz/tests/fuzz/$t"
      marker="$work/.started-$t"; touch "$marker"
      if ! (cd "$work" && TMPDIR="$work" "$bin" "$corpus" "$ROOT/tests/fuzz/corpus/${t#fuzz_}" "${extra[@]}" \
             -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
             -artifact_prefix="$work/crashes/$t-" -print_final_stats=1 > "$work/$t.log" 2>&1) &&
         ! { [ "$t" = fuzz_rawlog ] &&
             [ -n "$(find "$work/crashes" -name "$t-oom-*" -newer "$marker")" ] &&
             [ -z "$(find "$work/crashes" -name "$t-*" ! -name "$t-oom-*" -newer "$marker")" ]; }; then
        failed+=("$t")
        log "$t FOUND A CRASH (artifacts in $work/crashes):"; tail -40 "$work/$t.log" >&2
      elif [ -n "$(find "$work/crashes" -name "$t-oom-*" -newer "$marker")" ]; then
        log "$t: out-of-memory inputs only, inside MRPT's deserialiser (D1, docs/reliability.md)"
      fi
      grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb|^#[0-9]+.*DONE" "$work/$t.log" | sed "s/^/  $t /" >&2 || true
    done
    [ "${#failed[@]}" -eq 0 ] || { log "fuzz targets with findings: ${failed[*]}"; exit 1; }
    ;;
  shared)
    # Shared libraries (as MRPT ships them): build, install into a scratch prefix, then a
    # separate project uses them through find_package(lidarseg) and the core through
    # pkg-config, and an installed tool runs from the prefix (its RPATH finds the libraries).
    install_deps
    dir="$ROOT/build/shared"
    configure_build "$dir" -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON \
      -DLIDARSEG_BUILD_TESTS=OFF -DLIDARSEG_BUILD_BENCHMARKS=OFF
    cmake -DLIDARSEG_BUILD_DIR="$dir" -DCONSUMER_SOURCE_DIR="$ROOT/tests/package/consumer" \
      -DWORK_DIR="$dir/package" -DRAWLOG="$DEFAULT_RAWLOG" -DOPTIONS="$ROOT/config/default.ini" \
      -P "$ROOT/tests/package/run_consumer.cmake"
    ls "$dir"/package/prefix/lib*/liblidarseg_core.so* >/dev/null || { log "no shared liblidarseg_core.so installed"; exit 1; }
    "$dir/package/prefix/bin/lidarseg-segment" -q -n 20 "$DEFAULT_RAWLOG" | head -3
    log "shared libraries: built, installed and used"
    ;;
  tsan)
    install_deps
    dir="$ROOT/build/tsan"
    if [ ! -f "$dir/CMakeCache.txt" ]; then
      cmake -S "$ROOT" -B "$dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLIDARSEG_TSAN=ON \
        -DLIDARSEG_BUILD_TESTS=ON -DLIDARSEG_BUILD_BENCHMARKS=OFF
    fi
    # The parallel batch runner (its jobs are processes, each single-threaded in lidarseg's
    # code) and the code meant to be shared by threads: the matcher's per-thread scratch.
    cmake --build "$dir" --parallel "$JOBS" --target lidarseg-batch lidarseg-simulate lidarseg-odometry \
      test_BatchApp test_SegmentMatcher test_SegmentOdometry
    export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$ROOT/tests/sanitizers/tsan.supp"
    ctest --test-dir "$dir" --output-on-failure --parallel "$JOBS" --timeout 900 \
      -R "^(BatchApp|SegmentMatcher|SegmentOdometry|MatcherMotions|app\.lidarseg-batch)"
    ;;
  real)
    install_deps
    build_release
    out="$ROOT/build/results/real"
    mkdir -p "$out"
    python3 "$ROOT/tests/benchmarks/real_logs.py" --bin "$ROOT/build/release/apps" --config "$ROOT/config/default.ini" \
      --shared "$ROOT/../shared/datasets" --mrpt "$(dirname "$DEFAULT_RAWLOG")" --out "$out"
    ;;
  buildings)
    install_deps
    build_release
    mode="${2:-evaluate}"
    python3 "$ROOT/tests/benchmarks/buildings.py" "$mode" --bin "$ROOT/build/release/apps" \
      --out "$ROOT/build/results/buildings_$mode"
    ;;
  latency)
    install_deps
    build_release
    bin="$ROOT/build/release/apps"
    out="$ROOT/build/results/latency"
    mkdir -p "$out"
    shared="$ROOT/../shared/datasets"
    logs=()
    [ -d "$shared/radish-corrected" ] && logs+=("$shared"/radish-corrected/*.log.gz)
    [ -f "$shared/intel-mrpt/intel.rawlog" ] && logs+=("$shared/intel-mrpt/intel.rawlog")
    logs+=("$DEFAULT_RAWLOG" "/usr/share/mrpt/datasets/localization_demo.rawlog")
    # Simulated: both shipped worlds, two sensors (made on first use, deterministically).
    for world in hospital maze; do
      for sensor in lms100 utm30lx; do
        sim="$out/sim_${world}_${sensor}"
        [ -f "$sim.rawlog" ] || "$bin/lidarseg-simulate" --world "$ROOT/config/worlds/$world.world" \
          --trajectory "$ROOT/config/worlds/$world.traj" --sensor "$sensor" --seed 1 --camera-every 0 --out "$sim" >&2
        logs+=("$sim.rawlog")
      done
    done
    echo "| log | scans | median (µs) | p99 (µs) | max (µs) | max / median |"
    echo "|---|---:|---:|---:|---:|---:|"
    for f in "${logs[@]}"; do
      name="$(basename "$f")"; name="${name%%.*}"; name="${name// /_}"
      hz=()
      case "$f" in "$out"/sim_*) hz=(--scanner-hz 50) ;; esac
      [[ "$f" == *utm30lx* ]] && hz=(--scanner-hz 40)
      "$bin/lidarseg-odometry" -q --no-plots --no-gt "${hz[@]}" --out "$out/$name" "$f" > "$out/$name.txt" \
        || { log "FAILED: $f"; exit 1; }
      python3 - "$out/$name/summary.json" "$name" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["methods"]["lidarseg"]["time_ms"]
print("| %s | %d | %.1f | %.1f | %.1f | %.1f |" % (sys.argv[2], t["count"], t["median"] * 1e3, t["p99"] * 1e3,
      t["max"] * 1e3, t["max"] / t["median"]))
PY
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
