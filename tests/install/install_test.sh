#!/usr/bin/env bash
# install_out_of_tree (tests/install/CMakeLists.txt): install BUILD into a temporary prefix, build
# the out-of-tree example EXAMPLE against it with find_package(ohrp), and stand the robot with it
# under the installed ohrp_run/sim_host and the installed model and scenario; then pip-install
# the Python package (python/) into a venv, offline, and stand the robot with a Python controller
# using it against the installed programs.
#   install_test.sh BUILD EXAMPLE
set -euo pipefail
BUILD="$(realpath "$1")"
EXAMPLE="$(realpath "$2")"
SOURCE="$(realpath "$EXAMPLE/../..")"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
PREFIX="$TMP/prefix"
fail() { echo "install_test: FAIL: $*" >&2; exit 1; }

echo "== cmake --install $BUILD --prefix $PREFIX"
cmake --install "$BUILD" --prefix "$PREFIX" >"$TMP/install.log" 2>&1 \
  || { cat "$TMP/install.log" >&2; fail "cmake --install failed"; }

# the layout a user of the package relies on
LAYOUT="$(sed -n 's/^#define OHRP_LAYOUT_VERSION \([0-9]*\)$/\1/p' "$BUILD/include/ohrp/version.h")"
[ -n "$LAYOUT" ] || fail "no OHRP_LAYOUT_VERSION in $BUILD/include/ohrp/version.h"
for f in bin/sim_host bin/ohrp_run bin/hw_driver bin/posture bin/ohrp_view \
         lib/cmake/ohrp/ohrpConfig.cmake lib/cmake/ohrp/ohrpConfigVersion.cmake \
         lib/cmake/ohrp/ohrpTargets.cmake include/ohrp/version.h include/ohrp_shm.h \
         include/controllers/runner.h include/shm_bridge/layout.h include/cli/data_dir.h \
         "lib/libohrp_shm_c.so.$LAYOUT" lib/ohrp/libohrp_io_udp.so \
         share/ohrp/mjcf/hrp1s/hrp1s.xml share/ohrp/mjcf/hrp1s/selfcollision.yaml \
         share/ohrp/scenarios/stand.yaml share/ohrp/controllers/poses/hrp1s_halfsit.yaml \
         share/ohrp/tools/view/web/index.html share/ohrp/tools/scripts/plot_run.py; do
  [ -e "$PREFIX/$f" ] || fail "not installed: $f"
done
[ "$(readlink "$PREFIX/lib/libohrp_shm_c.so")" = "libohrp_shm_c.so.$LAYOUT" ] \
  || fail "lib/libohrp_shm_c.so does not link to the SOVERSION $LAYOUT library"
echo "installed: $(find "$PREFIX" -type f | wc -l) files; libohrp_shm_c.so -> libohrp_shm_c.so.$LAYOUT"

# nothing compiled into the installed programs and shared libraries names the checkout or the
# build folder (the data is found relative to the program: cli/data_dir.h)
for dir in "$SOURCE" "$BUILD"; do
  if hits="$(grep -l -F "$dir" "$PREFIX"/bin/* "$PREFIX"/lib/*.so* "$PREFIX"/lib/ohrp/*.so \
             "$PREFIX"/lib/cmake/ohrp/*.cmake 2>/dev/null)"; then
    fail "installed files name $dir: $hits"
  fi
done

echo "== the example against the prefix: find_package(ohrp)"
LAUNCHER=()
command -v ccache >/dev/null && LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$EXAMPLE" -B "$TMP/example" -DCMAKE_PREFIX_PATH="$PREFIX" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF "${LAUNCHER[@]}" >"$TMP/configure.log" 2>&1 \
  || { cat "$TMP/configure.log" >&2; fail "the example does not configure against $PREFIX"; }
grep -q "ohrp_DIR:PATH=$PREFIX/lib/cmake/ohrp" "$TMP/example/CMakeCache.txt" \
  || fail "find_package(ohrp) did not take the installed package: $(grep ohrp_DIR "$TMP/example/CMakeCache.txt")"
cmake --build "$TMP/example" -j 2 >"$TMP/build.log" 2>&1 \
  || { cat "$TMP/build.log" >&2; fail "the example does not build against $PREFIX"; }
# its include flags (imported targets' folders come as -isystem) name the prefix, not the checkout
flags="$TMP/example/CMakeFiles/stand_controller.dir/flags.make"
grep -q -F -- "-isystem $PREFIX/include" "$flags" || fail "the example does not include $PREFIX/include"
if grep -E -- "(-I|-isystem ?)$SOURCE/" "$flags"; then
  fail "the example's build reads headers from the checkout"
fi

echo "== the installed ohrp_run: stand.yaml with the example as the controller"
# the installed scenario, its controller replaced by the example (the same checks: standing,
# half-sitting height, feet carrying the weight, no creep, nothing rejected)
sed "s#^  - program: posture\$#  - program: $TMP/example/stand_controller#" \
  "$PREFIX/share/ohrp/scenarios/stand.yaml" >"$TMP/stand_example.yaml"
grep -q "program: $TMP/example/stand_controller" "$TMP/stand_example.yaml" \
  || fail "share/ohrp/scenarios/stand.yaml has no '  - program: posture' line to replace"
cd "$TMP"  # not in the checkout: only the prefix can be found
set +e
env -u OHRP_DATA_DIR "$PREFIX/bin/ohrp_run" "$TMP/stand_example.yaml" --out "$TMP/run" --no-plot \
  >"$TMP/run.log" 2>&1
code=$?
set -e
cat "$TMP/run.log"
[ "$code" -eq 0 ] || fail "ohrp_run exited $code (0 expected: the robot stands)"
grep -q "stand_controller: ohrp " "$TMP/run.log" || fail "the example's banner is not in the run's output"

echo "== the Python package: pip install of python/ into a venv, offline, with Debian's tools"
PY=/usr/bin/python3
"$PY" -m venv --system-site-packages "$TMP/venv" >"$TMP/venv.log" 2>&1 \
  || { cat "$TMP/venv.log" >&2; fail "python3 -m venv failed (python3-venv installed? ./ohrp setup)"; }
# from a copy: setuptools builds in the source folder (build/, *.egg-info), never in the checkout
cp -r "$SOURCE/python" "$TMP/python_src"
"$TMP/venv/bin/pip" install --no-index --no-build-isolation "$TMP/python_src" >"$TMP/pip.log" 2>&1 \
  || { cat "$TMP/pip.log" >&2; fail "pip install of $SOURCE/python failed"; }
VERSION="$(sed -n 's/^#define OHRP_VERSION_STRING "\(.*\)"$/\1/p' "$BUILD/include/ohrp/version.h")"
PIP_VERSION="$("$TMP/venv/bin/pip" show ohrp | sed -n 's/^Version: //p')"
[ "$PIP_VERSION" = "$VERSION" ] || fail "the Python package is version '$PIP_VERSION', the project $VERSION"
# imported outside the checkout, it takes the installed library of the ohrp on PATH
LIB="$(env -u OHRP_LIB PATH="$PREFIX/bin:$PATH" "$TMP/venv/bin/python" -c \
  'import ohrp, ohrp._capi as c, os; print(os.path.realpath(c.lib._name)); print(os.path.realpath(ohrp.__file__))')"
echo "$LIB"
[ "$(sed -n 1p <<<"$LIB")" = "$(realpath "$PREFIX/lib/libohrp_shm_c.so.$LAYOUT")" ] \
  || fail "the installed package did not load $PREFIX/lib/libohrp_shm_c.so.$LAYOUT"
case "$(sed -n 2p <<<"$LIB")" in "$TMP/venv/"*) ;; *) fail "ohrp was not imported from the venv";; esac
# and a controller using it stands the robot under the installed ohrp_run (stand_python.yaml's
# checks): the repository's example, copied out of the checkout, run by the venv's python
mkdir -p "$TMP/py"
sed "1s#.*#\#!$TMP/venv/bin/python#" "$SOURCE/python/examples/posture.py" >"$TMP/py/posture.py"
chmod +x "$TMP/py/posture.py"
sed -e "s#^  - program: python/examples/posture.py\$#  - program: $TMP/py/posture.py#" \
    -e "s#^    args: \[--ramp, \"2.0\"\]\$#    args: [--ramp, \"2.0\", --pose, $PREFIX/share/ohrp/controllers/poses/hrp1s_halfsit.yaml]#" \
  "$PREFIX/share/ohrp/scenarios/stand_python.yaml" >"$TMP/stand_pip.yaml"
grep -q "program: $TMP/py/posture.py" "$TMP/stand_pip.yaml" && grep -q -- "--pose, $PREFIX" "$TMP/stand_pip.yaml" \
  || fail "share/ohrp/scenarios/stand_python.yaml has not the program and args lines to replace"
set +e
env -u OHRP_DATA_DIR -u OHRP_LIB PATH="$PREFIX/bin:$PATH" "$PREFIX/bin/ohrp_run" "$TMP/stand_pip.yaml" \
  --out "$TMP/run_py" --no-plot >"$TMP/run_py.log" 2>&1
code=$?
set -e
cat "$TMP/run_py.log"
[ "$code" -eq 0 ] || fail "ohrp_run with the pip-installed package exited $code (0 expected: the robot stands)"
echo "install_test: PASS"
