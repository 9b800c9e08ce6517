#!/usr/bin/env bash
# install_debian_package (tests/install/CMakeLists.txt): cpack -G DEB from BUILD's CPackConfig
# into a temporary folder; the .deb must hold the programs, the package configuration, the C
# library with its SOVERSION and the model, and depend on Debian's MuJoCo and FCL packages.
#   package_test.sh BUILD
set -euo pipefail
BUILD="$(realpath "$1")"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
fail() { echo "package_test: FAIL: $*" >&2; exit 1; }

cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$TMP" >"$TMP/cpack.log" 2>&1 \
  || { cat "$TMP/cpack.log" >&2; fail "cpack -G DEB failed"; }
shopt -s nullglob
debs=("$TMP"/ohrp_*.deb)
[ "${#debs[@]}" -eq 1 ] || fail "expected one ohrp_*.deb in the cpack output, found ${#debs[@]}"
deb="${debs[0]}"
echo "package: $(basename "$deb"), $(du -k "$deb" | cut -f1) kB"

LAYOUT="$(sed -n 's/^#define OHRP_LAYOUT_VERSION \([0-9]*\)$/\1/p' "$BUILD/include/ohrp/version.h")"
dpkg-deb -c "$deb" | awk '{print $6}' >"$TMP/contents"
for pattern in '^\./usr/bin/sim_host$' '^\./usr/bin/ohrp_run$' \
               '^\./usr/lib/.*cmake/ohrp/ohrpConfig\.cmake$' \
               '^\./usr/lib/.*cmake/ohrp/ohrpConfigVersion\.cmake$' \
               "^\./usr/lib/.*libohrp_shm_c\.so\.$LAYOUT\$" \
               '^\./usr/include/ohrp/version\.h$' \
               '^\./usr/share/ohrp/mjcf/hrp1s/hrp1s\.xml$' '^\./usr/share/ohrp/scenarios/stand\.yaml$'; do
  grep -q -E "$pattern" "$TMP/contents" || fail "the package lacks $pattern"
done
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
for package in libmujoco2.2.2 libfcl0.7 libyaml-cpp0.7 python3; do
  [[ "$depends" == *"$package"* ]] || fail "Depends does not name $package"
done
echo "package_test: PASS ($(wc -l <"$TMP/contents") entries)"
