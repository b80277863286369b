#!/usr/bin/env bash
# Installs every build, test, plotting and benchmark dependency of conserve
# (petsc-dev: PETSc with OpenMPI, the Krylov and multigrid back ends)
# from Debian 12 packages (`time` is GNU time, for bench/run_paper.sh;
# python3-vtk9 and python3-meshio read the VTU output in the tests;
# calculix-ccx is the peer code of bench/run_calculix.sh).
# Idempotent: packages already present are skipped by apt, and the package
# index is refreshed only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev libopenblas-dev libmetis-dev
  petsc-dev openmpi-bin libscotch-dev
  libgmsh-dev gmsh
  libtomlplusplus-dev libcli11-dev libfmt-dev nlohmann-json3-dev libssl-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-matplotlib python3-numpy
  python3-vtk9 python3-meshio
  time calculix-ccx
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
