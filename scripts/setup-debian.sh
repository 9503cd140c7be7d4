#!/usr/bin/env bash
# Installs everything volcomp needs to build, run and test on Debian 12 (bookworm).
# Idempotent; run as root or with sudo available.
set -euo pipefail

packages=(
  # toolchain
  g++ cmake ninja-build pkg-config ccache clang-format git
  # Clang: the model core is also built and tested with it (tests/model/portable/check.sh)
  clang
  # libraries
  libeigen3-dev libmodbus-dev libasio-dev nlohmann-json3-dev libsystemd-dev
  libceres-dev libcli11-dev libspdlog-dev libfmt-dev
  # the HTML report: Vega, inlined into every report (python3, below, embeds it at build time)
  libjs-vega
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev socat python3 systemd
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
  # controller-table tests: LinuxCNC 2.9 (headless, simulated machine; python3 linuxcnc and hal
  # modules) and flock for its one-instance lock; NC program tests: its standalone interpreter
  # rs274 and its sample programs (nc_files)
  linuxcnc-uspace util-linux
  # robustness pass (scripts/robustness.sh): clang's libFuzzer and sanitizer runtimes; llvm for
  # the fuzz coverage report (scripts/fuzz-coverage.sh)
  libclang-rt-14-dev llvm
  # the LinuxCNC adapter: hal.h and liblinuxcnchal for volcompd's HAL userspace component
  linuxcnc-uspace-dev
  # the Debian package (cpack -G DEB, tests/package): man pages from --help, Depends from the
  # shared libraries (dpkg-shlibdeps, which CPack finds ELF files for with `file`), groff to
  # check the man pages
  help2man dpkg-dev file groff-base
)

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
