#!/usr/bin/env bash
# Installs what bpm needs from Debian 12 packages (as root) or says what is missing,
# then unpacks the real test meshes of libcgal-demo into .data/meshes.
# Used by both README commands; safe to run again (does nothing when all is there).
set -euo pipefail
cd "$(dirname "$0")/.."

# Package -> a file that proves it is installed.
declare -A NEED=(
  [build-essential]=/usr/bin/g++
  [cmake]=/usr/bin/cmake
  [libcgal-dev]=/usr/include/CGAL/Exact_predicates_inexact_constructions_kernel.h
  [libeigen3-dev]=/usr/include/eigen3/Eigen/Sparse
  [libhdf5-dev]=/usr/include/hdf5/serial/hdf5.h
  [zlib1g-dev]=/usr/include/zlib.h
  [libdeflate-dev]=/usr/include/libdeflate.h
  [libcli11-dev]=/usr/include/CLI/CLI.hpp
  [catch2]=/usr/include/catch2/catch.hpp
  [tetgen]=/usr/bin/tetgen
  [libcgal-demo]=/usr/share/doc/libcgal-dev/data.tar.gz
  [python3-h5py]=/usr/lib/python3/dist-packages/h5py/__init__.py
  [python3-numpy]=/usr/lib/python3/dist-packages/numpy/__init__.py
  [python3-vtk9]=/usr/lib/python3/dist-packages/vtkmodules/__init__.py
  [python3-meshio]=/usr/lib/python3/dist-packages/meshio/__init__.py
  [hdf5-tools]=/usr/bin/h5dump
  [pybind11-dev]=/usr/lib/cmake/pybind11/pybind11Config.cmake
  [python3-pybind11]=/usr/lib/python3/dist-packages/pybind11/__init__.py
  [python3-dev]=/usr/bin/python3-config
  [python3-pytest]=/usr/lib/python3/dist-packages/pytest/__init__.py
  [python3-pyflakes]=/usr/lib/python3/dist-packages/pyflakes/__init__.py
  [pkg-config]=/usr/bin/pkg-config
  [clang]=/usr/bin/clang++
  [libclang-rt-14-dev]=/usr/lib/llvm-14/lib/clang/14.0.6/lib/linux/libclang_rt.fuzzer-x86_64.a
  # DUNE 2.9 with UG (examples/dune: bpm-torsion, scripts/demo-solver.sh); Debian's UG is
  # built for MPI, so the MPI headers and libraries are needed too.
  [libdune-grid-dev]=/usr/include/dune/grid/uggrid.hh
  [libdune-uggrid-dev]=/usr/lib/x86_64-linux-gnu/cmake/dune-uggrid/dune-uggrid-config.cmake
  [libdune-istl-dev]=/usr/include/dune/istl/paamg/amg.hh
  [mpi-default-dev]=/usr/share/doc/mpi-default-dev/copyright
  # deal.II 9.4 for examples/dealii (-DBPM_WITH_DEALII=ON, scripts/test-dealii.sh); the
  # proof is its CMake config, which find_package(deal.II) reads.
  [libdeal.ii-dev]=/usr/share/cmake/deal.II/deal.IIConfig.cmake
  # The locale sources for de_DE.UTF-8 (generated below).
  [locales]=/usr/sbin/locale-gen
)
missing=()
for pkg in "${!NEED[@]}"; do
  [ -e "${NEED[$pkg]}" ] || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  IFS=$'\n' missing=($(sort <<<"${missing[*]}")); unset IFS
  if [ "$(id -u)" = 0 ]; then
    echo "setup: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >&2
    apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  else
    echo "setup: missing Debian packages: ${missing[*]}" >&2
    echo "setup: install them with:  sudo apt-get install ${missing[*]}" >&2
    exit 1
  fi
fi

# A locale with a decimal comma, which the unit test "... does not depend on the C
# locale" switches to (libbpm's files must read and write '.' under it). Debian
# compiles only C and POSIX; localedef adds this one.
if ! locale -a 2>/dev/null | grep -qix 'de_DE\.utf-\{0,1\}8'; then
  if [ "$(id -u)" = 0 ]; then
    echo "setup: generating the locale de_DE.UTF-8" >&2
    localedef -i de_DE -f UTF-8 de_DE.UTF-8
  else
    # Only the test suite needs it (its locale test fails with this same advice), so the
    # demo goes on without it.
    echo "setup: warning: the locale de_DE.UTF-8 is missing; the test suite needs it:" >&2
    echo "setup:   sudo localedef -i de_DE -f UTF-8 de_DE.UTF-8" >&2
  fi
fi

# Real meshes for tests and benchmarks: never committed, unpacked from the package.
if [ ! -f .data/meshes/femur.off ]; then
  mkdir -p .data
  tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C .data --strip-components=1 data/meshes
fi
