#!/usr/bin/env bash
# Installs every build, test and benchmark dependency from Debian packages.
# Idempotent: does nothing when all packages are already installed.
set -euo pipefail

PACKAGES=(
  cmake g++ make pkg-config
  libmrpt-dev mrpt-apps mrpt-common
  libeigen3-dev libopencv-dev libsuitesparse-dev libspectra-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libcereal-dev nlohmann-json3-dev zlib1g-dev libpng-dev libnanoflann-dev
  librosbag-storage-dev libroscpp-core-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev
  python3 python3-matplotlib time
  # The report page's browser test (tests/browser): headless Chromium, a font
  # for its text, PIL to read its screenshot.
  chromium fonts-dejavu-core python3-pil
  clang libclang-rt-14-dev  # libFuzzer and clang's sanitizer runtimes (scripts/fuzz.sh)
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  SUDO="sudo"
fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${PACKAGES[@]}"
