#!/usr/bin/env bash
# Builds the Debian package from BUILD_DIR (cpack -G DEB), unpacks it into a scratch root and
# checks what it installs: the control fields (Depends from dpkg-shlibdeps), the file list, the
# installed programs (run from the scratch root: --version, `volcompd --check-config` on every
# example daemon configuration, `volcomp check` on the example model), the man pages (groff
# without a warning) and the unit (systemd-analyze verify, alone and with the real-time drop-in).
#
# The package is unpacked with `dpkg -x`, which needs no root and no dpkg database: it writes the
# data archive where `dpkg -i` would. `dpkg --root DIR -i` refuses to run unprivileged ("requires
# superuser privilege"); with --force-not-root it needs a hand-made database in DIR and
# --force-depends, since that database knows none of the dependencies, so it would check less than
# it seems to. The package has no maintainer scripts (checked below), so -x skips nothing -i runs.
# Usage: check_package.sh BUILD_DIR WORK_DIR. Run by CTest (package_deb, label package).
set -euo pipefail
build="$(cd "$1" && pwd)"
work="$2"
rm -rf "$work"
mkdir -p "$work"
fail() {
  echo "FAIL: $*" >&2
  exit 1
}

echo "== cpack -G DEB"
cpack --config "$build/CPackConfig.cmake" -G DEB -B "$work/out" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log"; fail "cpack"; }
debs=("$work"/out/*.deb)
[ "${#debs[@]}" -eq 1 ] && [ -f "${debs[0]}" ] || fail "expected one .deb in $work/out"
deb="${debs[0]}"
echo "$(basename "$deb"): $(stat -c %s "$deb") bytes"

echo "== control"
dpkg-deb --field "$deb" Package Version Architecture Depends Recommends
[ "$(dpkg-deb --field "$deb" Package)" = volcomp ] || fail "package name"
depends="$(dpkg-deb --field "$deb" Depends)"
for lib in libc6 libstdc++6 libmodbus5 libsystemd0 libspdlog1; do
  [[ "$depends" == *"$lib"* ]] || fail "Depends lacks $lib: $depends"
done
[ -z "$(dpkg-deb --ctrl-tarfile "$deb" | tar -t | grep -E 'preinst|postinst|prerm|postrm')" ] ||
  fail "the package has maintainer scripts"

echo "== file list"
dpkg-deb --contents "$deb" | awk '{print $6}' | sed 's|^\./|/|' | grep -v '/$' | sort >"$work/files"
cat "$work/files"
expected=(
  /usr/bin/volcomp /usr/bin/volcomp-sim /usr/sbin/volcompd
  /usr/lib/systemd/system/volcompd.service
  /usr/share/doc/volcomp/systemd/volcompd-realtime.conf
  /usr/share/doc/volcomp/systemd/volcompd-linuxcnc.conf
  /usr/share/doc/volcomp/examples/linuxcnc/volcomp.ini
  /usr/share/doc/volcomp/examples/linuxcnc/volcomp.hal
  /usr/share/doc/volcomp/README.md /usr/share/doc/volcomp/docs/daemon.md
  /usr/share/doc/volcomp/docs/model.md /usr/share/doc/volcomp/docs/model-file.md
  /usr/share/doc/volcomp/docs/commissioning.md
  /usr/share/volcomp/volcomp-model-1.schema.json
  /usr/share/doc/volcomp/examples/README.md
  /usr/share/doc/volcomp/examples/volcompd-modbus-tcp.json
  /usr/share/doc/volcomp/examples/volcompd-modbus-rtu.json
  /usr/share/doc/volcomp/examples/volcompd-can.json
  /usr/share/doc/volcomp/examples/vmc-xyfz-21.json
  /usr/share/doc/volcomp/examples/sim-vmc.json
  /usr/share/man/man1/volcomp.1.gz /usr/share/man/man1/volcomp-sim.1.gz
  /usr/share/man/man8/volcompd.8.gz
)
for file in "${expected[@]}"; do
  grep -qxF "$file" "$work/files" || fail "missing $file"
done
# Nothing else: no headers, static libraries, /usr/local or /etc files.
unexpected="$(grep -vE '^/usr/(bin/volcomp(-sim)?|sbin/volcompd|lib/systemd/system/volcompd\.service|share/doc/volcomp/.+|share/volcomp/volcomp-model-1\.schema\.json|share/man/man[18]/volcomp(d|-sim)?\.[18]\.gz)$' "$work/files" || true)"
[ -z "$unexpected" ] || fail "unexpected files: $unexpected"

echo "== unpack into a scratch root (dpkg -x)"
root="$work/root"
dpkg -x "$deb" "$root"
examples="$root/usr/share/doc/volcomp/examples"

echo "== installed programs"
for program in usr/bin/volcomp usr/bin/volcomp-sim usr/sbin/volcompd; do
  if readelf -d "$root/$program" | grep -qE 'RPATH|RUNPATH'; then fail "$program has an RPATH"; fi
  if ldd "$root/$program" | grep -q 'not found'; then
    ldd "$root/$program"
    fail "$program: a library is missing"
  fi
  "$root/$program" --version
done
for config in "$examples"/volcompd-*.json; do
  # --check-config also checks the machine's side: that the CAN interface or the serial device
  # exists. Where it does not, the answer is exit status 2 and what to do about it.
  iface="$(sed -n 's/.*"interface": *"\([^"]*\)".*/\1/p' "$config")"
  device="$(sed -n 's/.*"device": *"\([^"]*\)".*/\1/p' "$config")"
  expected=""
  if [ -n "$iface" ] && [ ! -e "/sys/class/net/$iface" ]; then
    expected="$iface does not exist on this machine; create it with"
  elif [ -n "$device" ] && [ ! -e "$device" ]; then
    expected="$device does not exist: plug in the RS-485 adapter"
  fi
  if [ -n "$expected" ]; then
    status=0
    out="$("$root/usr/sbin/volcompd" --check-config --config "$config" 2>&1)" || status=$?
    [ "$status" -eq 2 ] && grep -qF "$expected" <<<"$out" ||
      fail "volcompd --check-config $(basename "$config"): status $status: $out"
    continue
  fi
  "$root/usr/sbin/volcompd" --check-config --config "$config" ||
    fail "volcompd --check-config $(basename "$config")"
done
"$root/usr/bin/volcomp" check "$examples/vmc-xyfz-21.json" >/dev/null || fail "volcomp check"

echo "== man pages"
for page in "$root"/usr/share/man/man*/*.gz; do
  warnings="$(zcat "$page" | LC_ALL=C.UTF-8 groff -k -man -Tutf8 -ww -z 2>&1)"
  [ -z "$warnings" ] || fail "$(basename "$page"): $warnings"
  zcat "$page" | grep -q '^\.SH "\?SEE ALSO' || fail "$(basename "$page") has no SEE ALSO"
done
zcat "$root/usr/share/man/man1/volcomp.1.gz" | grep -q '^\.SS "volcomp check"' ||
  fail "volcomp.1 lacks the verbs"

echo "== systemd-analyze verify"
# The unit as installed, its absolute paths moved into the scratch root (verify checks that
# ExecStart and the documentation exist).
unit="$root/usr/lib/systemd/system/volcompd.service"
grep -qx 'ExecStart=/usr/sbin/volcompd --config /etc/volcomp/volcompd.json' "$unit" ||
  fail "ExecStart: $(grep ExecStart= "$unit")"
verify() {
  local out status=0
  out="$(systemd-analyze verify "$1" 2>&1)" || status=$?
  [ -n "$out" ] && printf '%s\n' "$out"
  [ "$status" -eq 0 ] && [ -z "$out" ] || fail "systemd-analyze verify $1"
}
mkdir -p "$work/unit/volcompd.service.d"
sed -e "s|/usr/|$root/usr/|g" -e "s|/etc/volcomp/volcompd.json|$examples/volcompd-modbus-tcp.json|" \
  "$unit" >"$work/unit/volcompd.service"
verify "$work/unit/volcompd.service"
echo "unit verifies"
mkdir -p "$work/unit-realtime/volcompd.service.d"
cp "$work/unit/volcompd.service" "$work/unit-realtime/"
cp "$root/usr/share/doc/volcomp/systemd/volcompd-realtime.conf" \
  "$work/unit-realtime/volcompd.service.d/realtime.conf"
verify "$work/unit-realtime/volcompd.service"
echo "unit with the real-time drop-in verifies"
echo "package OK"
