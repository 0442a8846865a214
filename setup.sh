#!/usr/bin/env bash
# Installs, from Debian packages only, whatever fnopt needs to build and run. Idempotent: a
# package that is already installed is not touched, so a second run does nothing.
set -euo pipefail

packages=(
  cmake g++ make ninja-build pkg-config ccache
  libeigen3-dev libfftw3-dev libhdf5-dev libcli11-dev libgtest-dev libsuitesparse-dev
  libtorch-dev
  # Debian's libtorch links the reference BLAS through the libblas.so.3 alternative; OpenBLAS
  # switches that alternative and makes the FNO's dense layers ~5x faster (docs/design.md §9).
  libopenblas0-openmp
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -eq 0 ]] || sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
echo "setup: all dependencies present"
