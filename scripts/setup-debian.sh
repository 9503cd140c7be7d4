#!/usr/bin/env bash
# Installs what volcomp needs on Debian 12 (bookworm). Idempotent; run as root or with sudo.
#
#   setup-debian.sh --demo   what the demo builds and runs: the toolchain and the libraries of
#                            volcomp, volcompd and volcomp-sim (scripts/demo.sh)
#   setup-debian.sh          everything: the above, and what the tests, the benchmarks, the
#                            robustness pass and the Debian package use (scripts/test.sh)
set -euo pipefail

demo=(
  # toolchain (ccache: a second build of the same sources takes seconds)
  g++ cmake ninja-build pkg-config ccache
  # libraries of the three programs
  libeigen3-dev libmodbus-dev libasio-dev nlohmann-json3-dev libsystemd-dev
  libceres-dev libcli11-dev libspdlog-dev libfmt-dev
  # the HTML report: Vega, inlined into every report (python3 embeds it at build time); the
  # demo's own progress display is python3 too
  libjs-vega python3
)
all=(
  "${demo[@]}"
  clang-format git
  # the clang pass of the test command: sanitizers, libFuzzer, and the model built without the
  # run-time dispatch; llvm for the fuzz coverage report (scripts/fuzz-coverage.sh)
  clang libclang-rt-14-dev llvm
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev socat systemd
  # an independent Modbus master driving the server role (tests/e2e/modbus_server_e2e_test.cpp)
  mbpoll
  # the report opened in a headless browser
  chromium
  # the platform's pacing baseline the daemon's 1 kHz figures are compared with (bench/daemon/run_1khz.sh)
  rt-tests
  # the model format's JSON Schema checked against the examples (tests/config/schema_test.py)
  python3-jsonschema
  # CAN tests in a QEMU guest (this kernel may have no CAN): emulator, busybox, can-utils
  qemu-system-x86 busybox-static can-utils
  # LinuxCNC 2.9 (headless, simulated machine; its python3 linuxcnc and hal modules; flock for
  # its one-instance lock) for the LinuxCNC tests, its rs274 interpreter and sample programs for
  # the NC tests, and hal.h and liblinuxcnchal for volcompd-linuxcnc
  linuxcnc-uspace linuxcnc-uspace-dev util-linux
  # the Debian packages (cpack -G DEB, tests/package): man pages from --help, Depends from the
  # shared libraries (dpkg-shlibdeps, which CPack finds ELF files for with `file`), groff to
  # check the man pages
  help2man dpkg-dev file groff-base
)

packages=("${all[@]}")
case "${1:-}" in
  --demo) packages=("${demo[@]}") ;;
  "") ;;
  *) echo "usage: setup-debian.sh [--demo]" >&2; exit 2 ;;
esac

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all packages present"
fi
