#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages only), then configures and builds Talus.
# Idempotent: a second run installs nothing and rebuilds only what changed.
#   scripts/setup.sh [--build-dir DIR] [--build-type Release|Debug|RelWithDebInfo] [--sanitize]
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="$repo/build"
build_type=Release
sanitize=OFF
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --build-type) build_type="$2"; shift 2 ;;
    --sanitize) sanitize=ON; shift ;;
    *) echo "setup.sh: unknown option '$1'" >&2; exit 2 ;;
  esac
done

# libopenblas0-serial becomes the BLAS and LAPACK that CHOLMOD and UMFPACK call (Debian's
# alternatives; the reference BLAS otherwise): a beam tangent of 4068 unknowns factors in 3.6 ms
# instead of 7.6. The serial flavour keeps BLAS threads from competing with OpenMP's.
# python3-paraview brings ParaView's VTK with the XDMF readers the tests open run.xmf with
# (Debian's python3-vtk9 has none); it replaces python3-vtk9.
packages=(
  build-essential cmake pkg-config git
  libeigen3-dev libsuitesparse-dev libsundials-dev libopenblas0-serial
  trilinos-all-dev libopenmpi-dev openmpi-bin
  libhdf5-dev zlib1g-dev libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev libmuparser-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-matplotlib python3-h5py python3-paraview python3-yaml
)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$p")
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} packages present"
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S "$repo" -B "$build_dir" -DCMAKE_BUILD_TYPE="$build_type" -DTALUS_SANITIZE="$sanitize" >/dev/null
cmake --build "$build_dir" -j "$jobs"
echo "setup: built $build_type in $build_dir"
