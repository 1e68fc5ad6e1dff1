#!/usr/bin/env bash
# One-stop set-up for a fresh Debian (bookworm) machine:
#   bash scripts/setup.sh run    install what is missing, build (Release), run the default case
#   bash scripts/setup.sh test   install what is missing, build, run the whole test suite
#   bash scripts/setup.sh build  install what is missing and build only
# Installing needs root (apt-get); it is skipped when every package is already present.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake make pkg-config git clang-format
  libopenmpi-dev openmpi-bin libhypre-dev libhdf5-openmpi-dev
  libfftw3-dev libfftw3-mpi-dev
  libtomlplusplus-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-dolfinx python3-meshio python3-h5py python3-matplotlib python3-pytest python3-numpy
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing ${#missing[@]} missing Debian package(s): ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "== all Debian packages present"
fi

# MPI as root (CI runs as root) and with more ranks than cores.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1

case "${1:-build}" in
  run) make run ;;
  test) make test ;;
  build) make build ;;
  *) echo "usage: $0 run|test|build" >&2; exit 2 ;;
esac
