#!/usr/bin/env bash
# Installs the Debian packages rcsim needs. Idempotent: a quick no-op when all are present;
# runs `apt-get update` only when something must be installed.
set -euo pipefail
PACKAGES=(
  cmake g++ make pkg-config git
  libsystemc-dev libboost-dev libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libyaml-cpp-dev libcli11-dev zlib1g-dev
  bcc bin86 nasm python3 libx86emu-dev
  parallel libxml2-utils   # the regression tests: the GNU parallel recipe, JUnit checked by xmllint
  time                     # peak RSS of the memory tests (/usr/bin/time)
  gdb                      # the gdb stub's test drives Debian's gdb (tests/scenarios/debug)
  python3-serial           # pyserial: the pty backend's end-to-end tests (tests/scenarios/host)
  gtkwave                  # vcd2fst: the VCD test loads the trace with GTKWave's reader (tests/scenarios/trace)
  tao-pegtl-dev            # the Structured Text parser (main_cpu/st)
  chromium                 # the monitor's page test (headless; tests/scenarios/monitor/page_test.py)
  lcov                     # lcov and genhtml read --coverage's tracefiles (tests/scenarios/coverage, docs/tools.md)
  libmodbus-dev            # rcsim run --modbus: the Modbus TCP server (scenarios/modbus)
  libnlopt-dev             # rcsim search: the derivative-free optimisers (scenarios/search)
  python3-pymodbus         # its tests' client (tests/scenarios/modbus)
  python3-serial-asyncio   # pymodbus 3.0's client package imports it (Debian only recommends it)
  mbpoll                   # docs/monitor.md's Modbus command lines, run by tests/scenarios/modbus
  srecord                  # srec_cat writes the Motorola S-record images rcsim loads (tests/models)
  slurmctld slurmd slurm-client munge  # the one-node Slurm cluster the sweep recipe runs on (label cluster)
)
missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
