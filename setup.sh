#!/usr/bin/env bash
# Installs, from Debian packages only, whatever fnopt needs to build and run; `--tests` also what
# only the tests need. Idempotent: a package that is already installed is not touched, so a
# second run does nothing.
set -euo pipefail

case "${1:-}" in
  "") tests=0 ;;
  --tests) tests=1 ;;
  *) echo "setup: unknown option '$1' (the only option is --tests)" >&2; exit 2 ;;
esac

packages=(
  cmake g++ make ninja-build pkg-config ccache
  libeigen3-dev libfftw3-dev libhdf5-dev libcli11-dev libgtest-dev libsuitesparse-dev
  libtorch-dev
  # Triangle-mesh obstacles: reading OBJ files (io/obj_mesh, docs/design.md §14).
  libtinyobjloader-dev
  # Work beyond one machine: mpirun fnopt train / compare / stability (docs/design.md §12).
  libopenmpi-dev openmpi-bin
  # fnopt view: the web server and three.js.
  libcpp-httplib-dev libjs-three
  # Debian's libtorch links the reference BLAS through the libblas.so.3 alternative; OpenBLAS
  # switches that alternative and makes the FNO's dense layers ~5x faster (docs/design.md §9).
  libopenblas0-openmp
  # The Python module fnopt, for Debian's own python3 (docs/api.md).
  pybind11-dev python3-dev python3-numpy python3-scipy
)
# Chromium, for the test that draws the viewer's page headless (~40 s and 81 MB to install; the
# test is skipped without it, docs/design.md §11).
((tests)) && packages+=(chromium)
# The Python module's tests; venv and pip for the test of `pip install .` into a virtual environment.
((tests)) && packages+=(python3-pytest python3-venv python3-pip)
# The PyTorch bridge fnopt.torch under torch.autograd.gradcheck (python/tests/test_adjoint.py;
# skipped without it).
((tests)) && packages+=(python3-torch)

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
