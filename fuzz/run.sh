#!/usr/bin/env bash
# fuzz/run.sh [SECONDS] [BUILD_DIR]: builds the libFuzzer targets with clang (fuzz/CMakeLists.txt,
# in BUILD_DIR, default build/fuzz/ of the repository) and runs each for SECONDS (default 15)
# on a copy of its seed corpus (fuzz/corpus/NAME/). With OHRP_FUZZ_SEED set (ctest sets 1),
# each target runs a fixed number of inputs from that seed instead (OHRP_FUZZ_RUNS_NAME or the
# defaults below, a few seconds each), SECONDS only capping it: the same inputs every run, so
# CI is a reproducible check; a run without the seed explores new inputs. Exit 0 when none crashed; otherwise the
# crashing input is left in BUILD_DIR/crashes/ and the exit is 1. ctest's `fuzz` label calls it.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
SECONDS_EACH="${1:-15}"
BUILD="$(realpath -m "${2:-$HERE/../build/fuzz}")"
TARGETS=(scenario segment_header signal_word udp_packet pose trajectory footsteps vrml)
# inputs per target with a fixed seed (1-5 s each on this project's 2-core machines, 29 s for
# all; ctest caps each at 7 s, so that the label stays under a minute even on a loaded machine)
declare -A RUNS=([scenario]=25000 [segment_header]=200000 [signal_word]=25000
                 [udp_packet]=500000 [pose]=25000
                 [trajectory]=200000 [footsteps]=25000 [vrml]=25000)

# clang and libFuzzer (Debian: clang, libfuzzer-14-dev; ./ohrp setup installs them)
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found: run ./ohrp setup" >&2; exit 2; }

# configure once, build what changed
if [ ! -f "$BUILD/CMakeCache.txt" ]; then
  cmake -S "$HERE" -B "$BUILD" -DCMAKE_CXX_COMPILER=clang++ >"$BUILD.configure.log" 2>&1 \
    || { cat "$BUILD.configure.log" >&2; exit 2; }
  rm -f "$BUILD.configure.log"
fi
cmake --build "$BUILD" -j "${OHRP_FUZZ_JOBS:-2}" >"$BUILD/build.log" 2>&1 \
  || { grep -E -A5 "error" "$BUILD/build.log" | head -40 >&2; exit 2; }

# each fuzzer: new inputs go to a scratch corpus, the repository's seeds are only read
mkdir -p "$BUILD/crashes"
status=0
for name in "${TARGETS[@]}"; do
  work="$BUILD/corpus/$name"
  mkdir -p "$work"
  log="$BUILD/$name.log"
  fixed=()
  if [ -n "${OHRP_FUZZ_SEED:-}" ]; then
    rm -rf "$work" && mkdir -p "$work"  # the same starting corpus every run
    var="OHRP_FUZZ_RUNS_${name}"
    fixed=(-seed="$OHRP_FUZZ_SEED" -runs="${!var:-${RUNS[$name]}}")
  fi
  if "$BUILD/${name}_fuzz" "$work" "$HERE/corpus/$name" "${fixed[@]}" -max_total_time="$SECONDS_EACH" \
       -timeout=10 -rss_limit_mb=2048 -artifact_prefix="$BUILD/crashes/${name}-" \
       -print_final_stats=1 >"$log" 2>&1; then
    runs="$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")"
    echo "fuzz: $name: ok, $runs inputs (log: $log)"
  else
    echo "fuzz: $name: FAILED (log: $log, input in $BUILD/crashes/)" >&2
    grep -E -m20 "ERROR|runtime error|SUMMARY|Test unit written|#0 |#1 |#2 " "$log" >&2 || true
    status=1
  fi
done
exit $status
