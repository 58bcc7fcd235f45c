#!/usr/bin/env bash
# Installs madsfm's build, test and end-to-end dependencies from Debian's packages when they are
# missing. As root it runs apt-get; otherwise it lists what is missing and fails.
set -euo pipefail
PACKAGES=(
  cmake g++ make ccache pkg-config
  libeigen3-dev libceres-dev libgoogle-glog-dev libgflags-dev
  nlohmann-json3-dev libsqlite3-dev sqlite3 zlib1g-dev libpng-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  colmap python3-numpy
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-pytest python3-pip python3-setuptools python3-wheel
  dpkg-dev
  slurmctld slurmd slurm-client munge
)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "madsfm: missing Debian packages: ${missing[*]}" >&2
  echo "madsfm: run as root, or: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi
echo "madsfm: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -q >&2
apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
