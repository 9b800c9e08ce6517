#!/usr/bin/env bash
# Tests the `ohrp` script (the command surface): wrong names are refused before anything is
# built, the build is skipped when nothing changed since the last complete one and run when
# something did, and `demo --out DIR` puts its runs into DIR. Usage: ohrp_script_test.sh SOURCE_DIR
set -u
ROOT="$1"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# wrong names: exit 2 with the reason, and no build started (the build folder stays empty)
export OHRP_BUILD_DIR="$TMP/empty-build"
for args in "run nosuch" "compare nosuch" "bench nosuch" "video $TMP/nosuch" "view $TMP/nosuch" \
            "compare-logs $TMP/nosuch.csv $TMP/nosuch2.csv" "identify $TMP/nosuch.csv" \
            "sweep $TMP/nosuch.yaml"; do
  # shellcheck disable=SC2086
  out="$(timeout 60 "$ROOT/ohrp" $args 2>&1)"; rc=$?
  [ "$rc" -eq 2 ] || fail "'ohrp $args' gave exit $rc, not 2: $out"
  echo "$out" | grep -q "nosuch" || fail "'ohrp $args' did not name what is missing: $out"
  [ -z "$(ls -A "$OHRP_BUILD_DIR" 2>/dev/null)" ] || fail "'ohrp $args' started a build: $out"
done

# a build folder whose programs print their arguments, built after every source was saved
B="$TMP/build"
mkdir -p "$B/bin"
for p in sim_host ohrp_run; do
  printf '#!/bin/sh\necho "%s $*"\n' "$p" >"$B/bin/$p"
  chmod +x "$B/bin/$p"
done
touch "$B/CMakeCache.txt"
touch "$B/.ohrp-built"
export OHRP_BUILD_DIR="$B"

# nothing changed: no build, the program runs at once
out="$("$ROOT/ohrp" run stand --no-plot 2>&1)" || fail "'ohrp run stand' failed: $out"
echo "$out" | grep -q "building" && fail "built although nothing changed: $out"
echo "$out" | grep -q "^ohrp_run $ROOT/scenarios/stand.yaml --no-plot$" \
  || fail "'ohrp run stand' did not run ohrp_run on the scenario: $out"

# demo --out DIR: one folder per scenario in DIR, other options handed on
out="$("$ROOT/ohrp" demo --out "$TMP/demo" --quiet 2>&1)" || fail "'ohrp demo --out' failed: $out"
for s in stand walk_samplepd; do
  echo "$out" | grep -q "^ohrp_run $ROOT/scenarios/$s.yaml --out $TMP/demo/$s --quiet$" \
    || fail "'ohrp demo --out' did not put $s into $TMP/demo/$s: $out"
done
# its last line says how to replay the runs in the viewer
echo "$out" | tail -1 | grep -q "./ohrp view $TMP/demo/stand" \
  || fail "'ohrp demo' did not end with how to replay its runs in the viewer: $out"

# a source saved after the last build (here: a build older than every source): it builds (and
# fails, since this build folder is not a real one)
touch -d '2000-01-01' "$B/.ohrp-built"
out="$("$ROOT/ohrp" run stand 2>&1)"; rc=$?
echo "$out" | grep -q "building" || fail "did not build although sources changed: $out"
[ "$rc" -eq 2 ] || fail "a failed build gave exit $rc, not 2: $out"

# test --sanitize: its own build folder, configured with the sanitizers, and ctest run there with
# the sanitizers' options (cmake and ctest faked: they print their arguments and options)
mkdir -p "$TMP/fakebin"
printf '#!/bin/sh\necho "cmake $*"\n' >"$TMP/fakebin/cmake"
printf '#!/bin/sh\necho "ctest in $PWD: $* ASAN_OPTIONS=$ASAN_OPTIONS UBSAN_OPTIONS=$UBSAN_OPTIONS"\n' \
  >"$TMP/fakebin/ctest"
chmod +x "$TMP/fakebin/cmake" "$TMP/fakebin/ctest"
export OHRP_SANITIZE_BUILD_DIR="$TMP/asan"
out="$(PATH="$TMP/fakebin:$PATH" "$ROOT/ohrp" test --sanitize -R some 2>&1)" \
  || fail "'ohrp test --sanitize' failed: $out"
grep -q "^cmake -S $ROOT -B $TMP/asan .*-DOHRP_SANITIZE=ON" "$TMP/asan/configure.log" \
  || fail "'ohrp test --sanitize' did not configure $TMP/asan with OHRP_SANITIZE=ON: $out"
grep -q "^cmake --build $TMP/asan" "$TMP/asan/build.log" \
  || fail "'ohrp test --sanitize' did not build in $TMP/asan: $out"
echo "$out" | grep -q "^ctest in $TMP/asan: .*-R some ASAN_OPTIONS=.*detect_leaks=1.* UBSAN_OPTIONS=.*halt_on_error=1" \
  || fail "'ohrp test --sanitize' did not run ctest in $TMP/asan with the sanitizers' options: $out"
echo "PASS"
