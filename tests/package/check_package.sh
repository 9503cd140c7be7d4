#!/usr/bin/env bash
# Builds the Debian packages from BUILD_DIR (cpack -G DEB): volcomp and, when LINUXCNC is ON,
# volcomp-linuxcnc. Unpacks them into a scratch root and checks what they install: the control
# fields (Depends from dpkg-shlibdeps: volcomp's without LinuxCNC, volcomp-linuxcnc's with it and
# with volcomp of the same version), the file lists, the installed programs (run from the scratch
# root: --version and --help, `volcompd --check-config` on every example daemon configuration,
# `volcomp check` on the example model; the LinuxCNC example refused by volcompd and accepted by
# volcompd-linuxcnc), the man pages (groff without a warning) and the unit (systemd-analyze
# verify, alone, with the real-time drop-in and with the LinuxCNC drop-in).
#
# The package is unpacked with `dpkg -x`, which needs no root and no dpkg database: it writes the
# data archive where `dpkg -i` would. `dpkg --root DIR -i` refuses to run unprivileged ("requires
# superuser privilege"); with --force-not-root it needs a hand-made database in DIR and
# --force-depends, since that database knows none of the dependencies, so it would check less than
# it seems to. The packages have no maintainer scripts (checked below), so -x skips nothing -i
# runs.
# Usage: check_package.sh BUILD_DIR WORK_DIR [LINUXCNC: ON|OFF, default ON]. Run by CTest
# (package_deb, label package).
set -euo pipefail
build="$(cd "$1" && pwd)"
work="$2"
linuxcnc="${3:-ON}"
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
ls -l "$work"/out/*.deb || true
deb=""
lcnc_deb=""
for d in "${debs[@]}"; do
  [ -f "$d" ] || continue
  case "$(dpkg-deb --field "$d" Package)" in
    volcomp) deb="$d" ;;
    volcomp-linuxcnc) lcnc_deb="$d" ;;
    *) fail "unexpected package $(basename "$d")" ;;
  esac
done
[ -n "$deb" ] || fail "no volcomp .deb in $work/out"
if [ "$linuxcnc" = ON ]; then
  [ -n "$lcnc_deb" ] || fail "no volcomp-linuxcnc .deb in $work/out"
  [ "${#debs[@]}" -eq 2 ] || fail "expected two .deb in $work/out"
else
  [ -z "$lcnc_deb" ] && [ "${#debs[@]}" -eq 1 ] || fail "expected only volcomp's .deb in $work/out"
fi
no_maintainer_scripts() {
  [ -z "$(dpkg-deb --ctrl-tarfile "$1" | tar -t | grep -E 'preinst|postinst|prerm|postrm')" ] ||
    fail "$(basename "$1") has maintainer scripts"
}

echo "== control: volcomp"
dpkg-deb --field "$deb" Package Version Architecture Depends Recommends
version="$(dpkg-deb --field "$deb" Version)"
depends="$(dpkg-deb --field "$deb" Depends)"
for lib in libc6 libstdc++6 libmodbus5 libsystemd0 libspdlog1; do
  [[ "$depends" == *"$lib"* ]] || fail "Depends lacks $lib: $depends"
done
# The main package runs without LinuxCNC (Tk, GTK, Mesa...): that is volcomp-linuxcnc's.
! grep -qi linuxcnc <<<"$depends" || fail "volcomp's Depends names LinuxCNC: $depends"
no_maintainer_scripts "$deb"
if [ -n "$lcnc_deb" ]; then
  echo "== control: volcomp-linuxcnc"
  dpkg-deb --field "$lcnc_deb" Package Version Architecture Depends Recommends
  [ "$(dpkg-deb --field "$lcnc_deb" Version)" = "$version" ] || fail "volcomp-linuxcnc's Version"
  lcnc_depends="$(dpkg-deb --field "$lcnc_deb" Depends)"
  [[ "$lcnc_depends" == *"volcomp (= $version)"* ]] ||
    fail "volcomp-linuxcnc's Depends lacks volcomp (= $version): $lcnc_depends"
  [[ "$lcnc_depends" == *linuxcnc-uspace* ]] ||
    fail "volcomp-linuxcnc's Depends lacks LinuxCNC (liblinuxcnchal): $lcnc_depends"
  no_maintainer_scripts "$lcnc_deb"
fi

echo "== file list"
dpkg-deb --contents "$deb" | awk '{print $6}' | sed 's|^\./|/|' | grep -v '/$' | sort >"$work/files"
cat "$work/files"
expected=(
  /usr/bin/volcomp /usr/bin/volcomp-sim /usr/sbin/volcompd
  /usr/lib/systemd/system/volcompd.service
  /usr/share/doc/volcomp/systemd/volcompd-realtime.conf
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
# The LinuxCNC transport's files are volcomp-linuxcnc's.
linuxcnc_files='(/volcompd-linuxcnc[^/]*|/examples/linuxcnc/.*)$'
unexpected="$(grep -E "$linuxcnc_files" "$work/files" || true)"
[ -z "$unexpected" ] || fail "volcomp ships LinuxCNC files: $unexpected"
if [ -n "$lcnc_deb" ]; then
  echo "== file list: volcomp-linuxcnc"
  dpkg-deb --contents "$lcnc_deb" | awk '{print $6}' | sed 's|^\./|/|' | grep -v '/$' | sort \
    >"$work/lcnc-files"
  cat "$work/lcnc-files"
  for file in /usr/sbin/volcompd-linuxcnc /usr/share/man/man8/volcompd-linuxcnc.8.gz \
    /usr/share/doc/volcomp/systemd/volcompd-linuxcnc.conf \
    /usr/share/doc/volcomp/examples/linuxcnc/volcomp.ini \
    /usr/share/doc/volcomp/examples/linuxcnc/volcomp.hal \
    /usr/share/doc/volcomp/examples/linuxcnc/volcompd-linuxcnc.json; do
    grep -qxF "$file" "$work/lcnc-files" || fail "volcomp-linuxcnc: missing $file"
  done
  unexpected="$(grep -vE "$linuxcnc_files" "$work/lcnc-files" || true)"
  [ -z "$unexpected" ] || fail "volcomp-linuxcnc: unexpected files: $unexpected"
  # Installed together, the two packages must not both own a file (dpkg would refuse).
  shared="$(comm -12 "$work/files" "$work/lcnc-files")"
  [ -z "$shared" ] || fail "files in both packages: $shared"
fi

echo "== unpack into a scratch root (dpkg -x)"
root="$work/root"
dpkg -x "$deb" "$root"
programs=(usr/bin/volcomp usr/bin/volcomp-sim usr/sbin/volcompd)
if [ -n "$lcnc_deb" ]; then
  dpkg -x "$lcnc_deb" "$root"
  programs+=(usr/sbin/volcompd-linuxcnc)
fi
examples="$root/usr/share/doc/volcomp/examples"

echo "== installed programs"
for program in "${programs[@]}"; do
  if readelf -d "$root/$program" | grep -qE 'RPATH|RUNPATH'; then fail "$program has an RPATH"; fi
  if ldd "$root/$program" | grep -q 'not found'; then
    ldd "$root/$program"
    fail "$program: a library is missing"
  fi
  "$root/$program" --version
  "$root/$program" --help >"$work/help" || fail "$program --help"
  grep -q -- '--version' "$work/help" || fail "$program --help does not list --version"
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
if [ -n "$lcnc_deb" ]; then
  # The LinuxCNC example with its model from volcomp's examples (the example names it relative to
  # the source tree's config/linuxcnc).
  lcnc_config="$examples/linuxcnc/volcompd-linuxcnc-check.json"
  sed 's|"model": *"[^"]*"|"model": "../vmc-xyfz-21.json"|' \
    "$examples/linuxcnc/volcompd-linuxcnc.json" >"$lcnc_config"
  "$root/usr/sbin/volcompd-linuxcnc" --check-config --config "$lcnc_config" ||
    fail "volcompd-linuxcnc --check-config volcompd-linuxcnc.json"
  # Plain volcompd refuses it in one line naming the program and the package that have it.
  for mode in --check-config --probe; do
    status=0
    out="$("$root/usr/sbin/volcompd" $mode --config "$lcnc_config" 2>&1)" || status=$?
    [ "$status" -eq 2 ] && [ "$(wc -l <<<"$out")" -eq 1 ] &&
      grep -qF 'volcompd-linuxcnc (package volcomp-linuxcnc)' <<<"$out" ||
      fail "volcompd $mode on the LinuxCNC example: status $status: $out"
  done
  rm "$lcnc_config"
fi

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
if [ -n "$lcnc_deb" ]; then
  # The LinuxCNC drop-in starts volcompd-linuxcnc (root stands in for the LinuxCNC user).
  dropin="$root/usr/share/doc/volcomp/systemd/volcompd-linuxcnc.conf"
  grep -qx 'ExecStart=/usr/sbin/volcompd-linuxcnc --config /etc/volcomp/volcompd.json' "$dropin" ||
    fail "LinuxCNC drop-in ExecStart: $(grep ExecStart= "$dropin")"
  mkdir -p "$work/unit-linuxcnc/volcompd.service.d"
  cp "$work/unit/volcompd.service" "$work/unit-linuxcnc/"
  sed -e "s|/usr/|$root/usr/|g" -e "s|/etc/volcomp/volcompd.json|$examples/volcompd-modbus-tcp.json|" \
    -e 's/^User=.*/User=root/' -e 's/^Group=.*/Group=root/' \
    "$dropin" >"$work/unit-linuxcnc/volcompd.service.d/linuxcnc.conf"
  verify "$work/unit-linuxcnc/volcompd.service"
  echo "unit with the LinuxCNC drop-in verifies"
fi
echo "packages OK"
