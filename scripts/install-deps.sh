#!/usr/bin/env bash
# Installs the Debian packages pdimplicit needs when any is missing. Run as root (CI is root);
# otherwise prints the command to run. libopenblas0-serial takes over Debian's libblas.so.3 and liblapack.so.3
# alternatives from the reference BLAS: the direct solvers (MUMPS, CHOLMOD) factor several times faster on it
# (docs/solvers.md); serial, so that MPI ranks do not start threads of their own. It is wanted, not needed:
# without root a missing OpenBLAS is only reported.
set -euo pipefail
pkgs=(petsc-dev libhdf5-openmpi-dev hdf5-tools openmpi-bin cmake make gcc pkg-config time python3 python3-numpy python3-matplotlib python3-h5py)
wanted=(libopenblas0-serial)
installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${pkgs[@]}"; do installed "$p" || missing+=("$p"); done
absent=()
for p in "${wanted[@]}"; do installed "$p" || absent+=("$p"); done
[ ${#missing[@]} -eq 0 ] && [ ${#absent[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  if [ ${#missing[@]} -eq 0 ]; then
    echo "pdimplicit: ${absent[*]} would make the direct solvers faster: sudo apt-get install -y ${absent[*]}" >&2
    exit 0
  fi
  echo "pdimplicit needs: ${missing[*]}" >&2
  echo "install them with: sudo apt-get update && sudo apt-get install -y ${missing[*]} ${absent[*]}" >&2
  exit 1
fi
echo "installing: ${missing[*]} ${absent[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}" "${absent[@]}"
