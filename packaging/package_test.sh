#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# packaging_deb_install_test BUILD_DIR [ARCH]: builds the packages of BUILD_DIR with CPack.
# amd64 (the default): builds the amd64 packages,
# installs them into a scratch root (dpkg --root, maintainer scripts run chrootless with
# DPKG_ROOT), checks the files, the service user, the installed tools working together
# (excite design -> excite-gateway --dry-run on the example configuration), that the unit
# passes `systemd-analyze verify` with no complaint, and that removal takes the files away.
# Exit 0 passed, 1 failed (the first failed check is printed), 77 skipped (reason printed).
set -euo pipefail
build=$(cd "$1" && pwd)
arch=${2:-amd64}  # a cross build (arm64, armhf): the gateway package's contents only
work=$(mktemp -d "${TMPDIR:-/tmp}/excite-package-test.XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAILED: $*" >&2; exit 1; }
check() { local what=$1; shift; "$@" || fail "$what"; echo "ok: $what"; }

command -v dpkg >/dev/null || { echo "SKIPPED: dpkg is not installed (not a Debian system)"; exit 77; }
command -v systemd-analyze >/dev/null ||
  { echo "SKIPPED: systemd-analyze is missing (apt-get install systemd; toolchain/packages.txt)"; exit 77; }

cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/packages" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log" >&2; fail "cpack -G DEB"; }
version=$(sed -n 's/^set(CPACK_PACKAGE_VERSION "\(.*\)")$/\1/p' "$build/CPackConfig.cmake")
if [[ "$arch" != amd64 ]]; then
  # Cross: the target's package, unpacked (dpkg will not install another architecture's
  # package into a root without that architecture's libraries).
  gw="$work/packages/excite-gateway_${version}_${arch}.deb"
  declare -A machine=([arm64]=AArch64 [armhf]=ARM)
  check "excite-gateway_${version}_${arch}.deb built" test -f "$gw"
  check "excite-gateway: Architecture $arch" test "$(dpkg-deb -f "$gw" Architecture)" = "$arch"
  dpkg-deb -x "$gw" "$work/x"
  check "/usr/bin/excite-gateway is a ${machine[$arch]} executable" \
    grep -q "Machine: *${machine[$arch]}" <<<"$(readelf -h "$work/x/usr/bin/excite-gateway")"
  check "/usr/bin/excite-gateway is stripped" \
    bash -c "! readelf -S '$work/x/usr/bin/excite-gateway' | grep -q '\.debug_info'"
  check "unit installed" test -f "$work/x/usr/lib/systemd/system/excite-gateway.service"
  check "example configuration installed" \
    test -f "$work/x/usr/share/doc/excite-gateway/examples/gateway.example.toml"
  check "no excite-host package for $arch" test ! -e "$work/packages/excite-host_${version}_${arch}.deb"
  echo "package test ($arch): every check passed"
  exit 0
fi
gw="$work/packages/excite-gateway_${version}_amd64.deb"
host="$work/packages/excite-host_${version}_amd64.deb"
check "excite-gateway_${version}_amd64.deb built" test -f "$gw"
check "excite-host_${version}_amd64.deb built" test -f "$host"
check "excite-gateway: Architecture amd64" test "$(dpkg-deb -f "$gw" Architecture)" = amd64
check "excite-gateway: depends on libmodbus5" grep -q libmodbus5 <<<"$(dpkg-deb -f "$gw" Depends)"
check "excite-gateway: has a postinst" grep -q postinst <<<"$(dpkg-deb -I "$gw")"

root="$work/root"
mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates" "$root/etc"
touch "$root/var/lib/dpkg/status"
dpkg --root="$root" --log=/dev/null --force-depends --force-script-chrootless \
  -i "$gw" "$host" >"$work/dpkg.log" 2>&1 || { cat "$work/dpkg.log" >&2; fail "dpkg --root -i"; }
check "dpkg: excite-gateway installed" grep -q 'install ok installed' \
  <<<"$(dpkg --root="$root" -s excite-gateway)"
check "dpkg: excite-host installed" grep -q 'install ok installed' \
  <<<"$(dpkg --root="$root" -s excite-host)"

for f in usr/bin/excite-gateway usr/bin/excite usr/bin/excite-plant; do
  check "/$f is executable" test -x "$root/$f"
  check "/$f is stripped" bash -c "! readelf -S '$root/$f' | grep -q '\.debug_info'"
done
unit="$root/usr/lib/systemd/system/excite-gateway.service"
check "unit installed" test -f "$unit"
check "sysusers.d file installed" test -f "$root/usr/lib/sysusers.d/excite-gateway.conf"
check "example configuration installed" \
  test -f "$root/usr/share/doc/excite-gateway/examples/gateway.example.toml"
check "plant example installed" test -f "$root/usr/share/doc/excite-host/examples/alatiqi4x4.toml"
check "README installed" test -f "$root/usr/share/doc/excite-gateway/README.md"
if command -v systemd-sysusers >/dev/null; then
  check "postinst created user excite" grep -q '^excite:' "$root/etc/passwd"
  check "user excite is in group dialout" grep -Eq '^dialout:.*[:,]excite(,|$)' "$root/etc/group"
fi

# The unit: runs the installed binary as user excite, with the two capabilities, no --start.
exec_line=$(grep '^ExecStart=' "$unit")
check "unit runs /usr/bin/excite-gateway (installed)" grep -q ' /usr/bin/excite-gateway ' <<<"$exec_line"
if grep -q -- '--start' <<<"$exec_line"; then fail "unit passes --start: $exec_line"; fi
echo "ok: unit never passes --start"
check "unit: User=excite" grep -qx 'User=excite' "$unit"
check "unit: capabilities" grep -qx 'AmbientCapabilities=CAP_SYS_NICE CAP_IPC_LOCK' "$unit"
check "unit: Restart=on-failure" grep -qx 'Restart=on-failure' "$unit"
check "unit: LogsDirectory=excite" grep -qx 'LogsDirectory=excite' "$unit"
verify=$(systemd-analyze verify "$unit" 2>&1) || fail "systemd-analyze verify: $verify"
check "systemd-analyze verify: no complaint" test -z "$verify"

# The unit's command line as systemd hands it to the shell ("$$" -> "$", "%%" -> "%"), with the
# installed binary and scratch /etc/excite and /var/log/excite: a missing configuration, then
# a missing plan, are refused with exactly one line naming the file, exit 2 and 3 (no
# connection is attempted before either check).
cmd=${exec_line#ExecStart=}
cmd=${cmd//\$\$/\$}
cmd=${cmd//%%/%}
cmd=${cmd//\/usr\/bin\/excite-gateway/$root/usr/bin/excite-gateway}
cmd=${cmd//\/etc\/excite/$work/etc-excite}
cmd=${cmd//\/var\/log\/excite/$work/log-excite}
mkdir -p "$work/etc-excite" "$work/log-excite"
refused() {  # refused CODE NEEDLE: runs the unit's command, expects CODE and one line with NEEDLE
  local rc=0 err
  err=$(eval "$cmd" 2>&1 >/dev/null) || rc=$?
  [[ $rc -eq $1 && $(wc -l <<<"$err") -eq 1 && "$err" == *"$2"* ]] ||
    fail "unit command: expected exit $1 and one line naming $2, got exit $rc: $err"
  echo "ok: unit command refuses ($1): $err"
}
refused 2 "$work/etc-excite/gateway.toml"
cp "$root/usr/share/doc/excite-gateway/examples/gateway.example.toml" "$work/etc-excite/gateway.toml"
refused 3 "$work/etc-excite/gateway.plan"
check "no run log left by a refusal" test -z "$(ls "$work/log-excite")"

# The installed tools together: a plan designed by the installed excite passes the installed
# gateway's every check with the installed example configuration.
export LD_LIBRARY_PATH=""  # the host's libraries, as on a target with the Depends installed
"$root/usr/bin/excite" design -q --plant alatiqi4x4 --preset prbsUnc -o "$work/case.plan" ||
  fail "installed excite design"
"$root/usr/bin/excite-gateway" --dry-run --plan "$work/case.plan" \
  --config "$root/usr/share/doc/excite-gateway/examples/gateway.example.toml" >"$work/dry.txt" 2>&1 ||
  { cat "$work/dry.txt" >&2; fail "installed excite-gateway --dry-run on the example configuration"; }
echo "ok: installed excite-gateway --dry-run passes the example configuration and a designed plan"

dpkg --root="$root" --log=/dev/null --force-depends --force-script-chrootless \
  -r excite-gateway excite-host >"$work/dpkg-r.log" 2>&1 || { cat "$work/dpkg-r.log" >&2; fail "dpkg -r"; }
check "removed: binary gone" test ! -e "$root/usr/bin/excite-gateway"
check "removed: unit gone" test ! -e "$unit"
echo "package test: every check passed"
