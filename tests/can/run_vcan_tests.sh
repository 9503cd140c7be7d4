#!/usr/bin/env bash
# Runs the SocketCAN test executable on a real (virtual) CAN interface.
#
#   run_vcan_tests.sh [--cache DIR] [--mode auto|direct|qemu] [--timeout SECONDS] [--data DIR]
#                     [--copy PATH]... TEST_EXE [ARGS...]
#
# --data DIR: files the tests read (found through $VOLCOMP_CAN_DATA; copied into the guest).
# --copy PATH: a file or folder the tests use by its absolute path (e.g. volcomp-sim and volcompd
#         started as processes); copied into the guest at the same path, an executable with its
#         shared libraries and loader.
# direct: this kernel can create a vcan interface (CAN modules present and CAP_NET_ADMIN): a
#         uniquely named vcan interface is created, the tests run against it, it is deleted.
# qemu:   otherwise. Debian's kernel package (linux-image-6.1.0-NN-amd64, NN from
#         `apt-cache depends linux-image-amd64`) is downloaded with `apt-get download` (never
#         installed) into the cache directory and its kernel and four CAN modules are extracted.
#         An initramfs is built with busybox-static, the modules (can-dev, can, can-raw, vcan),
#         the (static) test executable, and can-utils' cansend/candump with their shared
#         libraries; its /init creates vcan0, runs the tests and prints RC=<exit status>. QEMU
#         boots it with software emulation (TCG) and the serial console is parsed for RC=.
# auto (default): direct when possible, else qemu.
# Exits with the tests' status; any failure to set up (no qemu, no network for the download,
# no RC= line) is a failure, never a skip.
set -euo pipefail

cache=""
mode=auto
timeout_s=600
data=""
copies=()
while [ $# -gt 0 ]; do
  case "$1" in
    --cache) cache="$2"; shift 2 ;;
    --mode) mode="$2"; shift 2 ;;
    --timeout) timeout_s="$2"; shift 2 ;;
    --data) data="$(readlink -f "$2")"; shift 2 ;;
    --copy) copies+=("$(readlink -f "$2")"); shift 2 ;;
    --) shift; break ;;
    -*) echo "run_vcan_tests: unknown option $1" >&2; exit 2 ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || { echo "usage: $0 [--cache DIR] [--mode auto|direct|qemu] TEST_EXE [ARGS...]" >&2; exit 2; }
test_exe="$(readlink -f "$1")"
shift
[ -x "$test_exe" ] || { echo "run_vcan_tests: FAIL: $test_exe is not executable" >&2; exit 1; }
cache="${cache:-$(dirname "$test_exe")/vm-cache}"
mkdir -p "$cache"

fail() { echo "run_vcan_tests: FAIL: $*" >&2; exit 1; }

# --- direct ------------------------------------------------------------------------------------
run_direct() {
  local iface="$1"
  shift
  echo "run_vcan_tests: running directly on $iface"
  ip link set up "$iface"
  local rc=0
  VOLCOMP_CAN_IFACE="$iface" VOLCOMP_CAN_DATA="$data" "$test_exe" "$@" || rc=$?
  ip link del "$iface" 2>/dev/null || true
  echo "RC=$rc"
  return "$rc"
}

if [ "$mode" != qemu ]; then
  iface="vcvt$$"
  iface="${iface:0:15}"
  if command -v ip >/dev/null && ip link add dev "$iface" type vcan 2>/dev/null; then
    run_direct "$iface" "$@"
    exit $?
  fi
  [ "$mode" = direct ] && fail "this kernel cannot create a vcan interface (no CAN support or no CAP_NET_ADMIN)"
  echo "run_vcan_tests: this kernel has no vcan; using a QEMU guest"
fi

# --- qemu --------------------------------------------------------------------------------------
for tool in qemu-system-x86_64 apt-get apt-cache dpkg-deb tar gzip ldd cansend candump flock; do
  command -v "$tool" >/dev/null || fail "$tool not found (run scripts/setup-debian.sh)"
done
busybox="$(command -v busybox || true)"
[ -n "$busybox" ] || fail "busybox not found (package busybox-static)"
{ ldd "$busybox" 2>&1 || true; } | grep -q "not a dynamic" ||
  fail "$busybox is not statically linked (install busybox-static)"

# 1. Debian's kernel package, downloaded once into the cache. Two runs at once (two build trees,
# or tests started by hand) download and extract one at a time; the others wait for it.
exec 9>"$cache/.download.lock"
flock 9
kernel_package() {
  apt-cache depends linux-image-amd64 2>/dev/null |
    sed -n 's/^ *Depends: \(linux-image-[0-9][^ ]*-amd64\)$/\1/p' | head -n 1
}
pkg="$(kernel_package)"
if [ -z "$pkg" ] && [ "$(id -u)" -eq 0 ] && ! ls "$cache"/linux-image-*-amd64_*.deb >/dev/null 2>&1; then
  # Images often ship without package lists: fetch them once.
  echo "run_vcan_tests: no package lists, running apt-get update"
  apt-get update -qq || true
  pkg="$(kernel_package)"
fi
if [ -z "$pkg" ]; then
  # No package lists (apt-get update never ran): use a kernel package already in the cache.
  deb="$(ls -1 "$cache"/linux-image-*-amd64_*.deb 2>/dev/null | sort -V | tail -n 1 || true)"
  [ -n "$deb" ] || fail "cannot find the kernel package (apt-cache depends linux-image-amd64 gave nothing; run apt-get update)"
else
  deb="$(ls -1 "$cache"/"${pkg}"_*.deb 2>/dev/null | tail -n 1 || true)"
  if [ -z "$deb" ]; then
    echo "run_vcan_tests: downloading $pkg"
    (cd "$cache" && apt-get download "$pkg" 2>&1 | grep -v "^W: Download is performed unsandboxed") ||
      fail "apt-get download $pkg failed"
    deb="$(ls -1 "$cache"/"${pkg}"_*.deb | tail -n 1)"
  fi
fi
kdir="$cache/$(basename "$deb" .deb)"
if [ ! -f "$kdir/.extracted" ]; then
  rm -rf "$kdir"
  mkdir -p "$kdir"
  # Only the kernel and the four CAN modules are needed out of ~400 MB.
  dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$kdir" --wildcards \
    './boot/vmlinuz-*' '*/kernel/drivers/net/can/dev/can-dev.ko*' '*/kernel/net/can/can.ko*' \
    '*/kernel/net/can/can-raw.ko*' '*/kernel/drivers/net/can/vcan.ko*' ||
    fail "cannot extract the kernel and CAN modules from $deb"
  touch "$kdir/.extracted"
fi
flock -u 9
vmlinuz="$(ls -1 "$kdir"/boot/vmlinuz-* | head -n 1)"
[ -f "$vmlinuz" ] || fail "no kernel image in $deb"

# 2. The initramfs.
work="$(mktemp -d "$cache/initrd.XXXXXX")"
trap 'rm -rf "$work"' EXIT
root="$work/root"
mkdir -p "$root"/{bin,mod,proc,sys,dev,tmp,data}
[ -z "$data" ] || cp -r "$data"/. "$root/data/"
cp "$busybox" "$root/bin/busybox"
for m in can-dev can can-raw vcan; do
  ko="$(find "$kdir/lib/modules" -name "$m.ko*" | head -n 1)"
  [ -n "$ko" ] || fail "module $m not found in $deb"
  case "$ko" in
    *.ko) cp "$ko" "$root/mod/$m.ko" ;;
    *.ko.xz) xz -dc "$ko" > "$root/mod/$m.ko" ;;
    *.ko.zst) zstd -qdc "$ko" > "$root/mod/$m.ko" ;;
    *) fail "unknown module format $ko" ;;
  esac
done
copy_with_libs() {  # copies an executable and, when dynamic, its libraries and loader
  local exe="$1" dest="$2"
  cp "$exe" "$root$dest"
  { ldd "$exe" 2>/dev/null || true; } | { grep -o '/[^ ]*' || true; } | while read -r lib; do
    [ -f "$lib" ] || continue
    mkdir -p "$root$(dirname "$lib")"
    cp -L "$lib" "$root$lib"
  done
}
for p in ${copies[@]+"${copies[@]}"}; do
  [ -e "$p" ] || fail "--copy $p: no such file"
  mkdir -p "$root$(dirname "$p")"
  if [ -d "$p" ]; then
    mkdir -p "$root$p" && cp -r "$p"/. "$root$p/"
  elif [ -x "$p" ]; then
    copy_with_libs "$p" "$p"
  else
    cp "$p" "$root$p"
  fi
done
copy_with_libs "$test_exe" /bin/volcomp-tests
copy_with_libs "$(command -v cansend)" /bin/cansend
copy_with_libs "$(command -v candump)" /bin/candump
# Test arguments, one per line, read back by /init.
: > "$root/args"
for a in "$@"; do printf '%s\n' "$a" >> "$root/args"; done
cat > "$root/init" <<'INIT'
#!/bin/busybox sh
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev 2>/dev/null
for m in can-dev can can-raw vcan; do insmod /mod/$m.ko || echo "init: insmod $m failed"; done
ip link add dev vcan0 type vcan && ip link set up vcan0
set --
while IFS= read -r a; do set -- "$@" "$a"; done < /args
cd /tmp
VOLCOMP_CAN_IFACE=vcan0 VOLCOMP_CAN_DATA=/data /bin/volcomp-tests "$@"
echo "RC=$?"
poweroff -f
INIT
chmod +x "$root/init"
(cd "$root" && find . | "$busybox" cpio -o -H newc 2>/dev/null | gzip -1 > "$work/initrd.gz")

# 3. Boot.
# One log per test executable, so that parallel CTest runs do not share it.
log="$cache/last-boot-$(basename "$test_exe").log"
echo "run_vcan_tests: booting $(basename "$vmlinuz") under QEMU (TCG)"
start=$(date +%s)
qrc=0
timeout "$timeout_s" qemu-system-x86_64 -accel tcg -cpu max -smp 2 -m 512 -nographic -no-reboot \
  -kernel "$vmlinuz" -initrd "$work/initrd.gz" \
  -append "console=ttyS0 quiet panic=-1" < /dev/null > "$log" 2>&1 || qrc=$?
tr -d '\r' < "$log"
echo "run_vcan_tests: guest finished after $(( $(date +%s) - start )) s (qemu status $qrc)"
rc_line="$(tr -d '\r' < "$log" | grep -a '^RC=[0-9]*$' | tail -n 1 || true)"
[ -n "$rc_line" ] || fail "no RC= line on the guest console (qemu status $qrc, log $log)"
rc="${rc_line#RC=}"
exit "$rc"
