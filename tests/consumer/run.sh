#!/bin/bash
# The installed bpm as a consumer sees it (ctest label "consumer"; tests/CMakeLists.txt).
#
#   run.sh install   BUILD SOURCE WORK LIBDIR   cmake --install BUILD into WORK/prefix, and
#                                              WORK/femur.bpm made by the built bpm-simplify
#   run.sh headers   BUILD SOURCE WORK LIBDIR   every WORK/prefix/include/bpm/*.h compiles alone
#                                              with only -IWORK/prefix/include, and includes
#                                              nothing but the C++ standard library and bpm
#   run.sh cmake     BUILD SOURCE WORK LIBDIR   tests/consumer built with find_package(bpm)
#   run.sh pkgconfig BUILD SOURCE WORK LIBDIR   consumer.cpp built with pkg-config --cflags --libs bpm
#   run.sh python    BUILD SOURCE WORK LIBDIR PYTHON PYDIR
#                                              the installed package WORK/prefix/PYDIR/bpm imported
#                                              and phi evaluated
set -euo pipefail
step=$1 build=$2 source=$3 work=$4 libdir=$5
prefix=$work/prefix
CXX=${CXX:-c++}

run_consumer() {  # the consumer on the femur, then on a missing file (exit 3: the bpm::InputError
                  # thrown in libbpm.so is caught by type in the program)
    "$1" "$work/femur.bpm" | tee "$work/$2.out"
    grep -q '^phi = ' "$work/$2.out"
    local rc=0
    "$1" "$work/missing.bpm" 2>"$work/$2.err" || rc=$?
    if [ "$rc" != 3 ] || ! grep -q 'missing.bpm' "$work/$2.err"; then
        echo "FAIL: a missing file gave exit $rc and: $(cat "$work/$2.err")" >&2
        exit 1
    fi
}

case $step in
install)
    rm -rf "$prefix"
    mkdir -p "$work"
    cmake --install "$build" --prefix "$prefix" >"$work/install.log"
    for f in "$prefix/$libdir/libbpm.so.0" "$prefix/$libdir/cmake/bpm/bpmConfig.cmake" \
             "$prefix/$libdir/cmake/bpm/bpmConfigVersion.cmake" "$prefix/$libdir/pkgconfig/bpm.pc" \
             "$prefix/include/bpm/version.h" "$prefix/bin/bpm-simplify"; do
        [ -e "$f" ] || { echo "FAIL: not installed: $f" >&2; exit 1; }
    done
    soname=$(objdump -p "$prefix/$libdir/libbpm.so.0" | awk '$1 == "SONAME" {print $2}')
    [ "$soname" = libbpm.so.0 ] || { echo "FAIL: SONAME is '$soname', not libbpm.so.0" >&2; exit 1; }
    "$prefix/bin/bpm-simplify" "$source/.data/meshes/femur.off" --ratio 0.1 --deterministic \
        -o "$work/femur.bpm" 2>"$work/simplify.log"
    echo "installed into $prefix (SONAME $soname); $work/femur.bpm written"
    ;;
headers)
    n=$(ls "$prefix"/include/bpm/*.h | wc -l)
    [ "$n" -gt 10 ] || { echo "FAIL: only $n headers installed" >&2; exit 1; }
    ls "$prefix"/include/bpm/*.h | xargs -P 2 -n 1 bash "$0" header "$build" "$source" "$work" "$libdir"
    echo "$n public headers compile alone with -I$prefix/include"
    ;;
header)  # one header (run by "headers")
    name=bpm/$(basename "$6")
    dep=$(mktemp)
    trap 'rm -f "$dep"' EXIT
    echo "#include \"$name\"" | $CXX -std=c++17 -x c++ -fsyntax-only -Wall -Wextra -Werror -MD -MF "$dep" \
        -I"$prefix/include" -
    # Only the header itself, bpm's other headers and the C/C++ standard library.
    bad=$(tr ' \\' '\n\n' <"$dep" | grep '^/' | grep -Ev "^$prefix/include/bpm/[^/]+\.h$" \
          | grep -Ev '^/usr/(include/c\+\+/|include/x86_64-linux-gnu/|lib/gcc/|include/[^/]+\.h$|include/(asm-generic|linux)/)' || true)
    if [ -n "$bad" ]; then
        echo "FAIL: $name includes headers outside bpm and the standard library:" >&2
        echo "$bad" >&2
        exit 1
    fi
    ;;
cmake)
    rm -rf "$work/cmake-build"
    cmake -S "$source/tests/consumer" -B "$work/cmake-build" -DCMAKE_BUILD_TYPE=Release \
          -DCMAKE_PREFIX_PATH="$prefix" >"$work/cmake-configure.log"
    cmake --build "$work/cmake-build" >"$work/cmake-build.log"
    run_consumer "$work/cmake-build/consumer" cmake
    ;;
pkgconfig)
    # README-BEGIN
    export PKG_CONFIG_PATH=$prefix/$libdir/pkgconfig
    $CXX -std=c++17 -O2 -o "$work/consumer-pc" "$source/tests/consumer/consumer.cpp" \
        $(pkg-config --cflags --libs bpm) -Wl,-rpath,"$(pkg-config --variable=libdir bpm)"
    # README-END
    run_consumer "$work/consumer-pc" pkgconfig
    ;;
python)
    python=$6 pydir=$7
    PYTHONPATH=$prefix/$pydir "$python" - "$work/femur.bpm" "$prefix" <<'PY'
import sys
import numpy as np
import bpm
assert bpm.__file__.startswith(sys.argv[2]), "imported %s, not the installed package" % bpm.__file__
f = bpm.read(sys.argv[1])
x = f.phi(np.array([0], dtype=np.int32), np.full((1, 3), 1.0 / 3))
lo, hi = f.original_vertices.min(axis=0), f.original_vertices.max(axis=0)
assert np.isfinite(x).all() and (x >= lo).all() and (x <= hi).all(), x
print("installed module %s: phi = %s" % (bpm.__file__, x[0]))
PY
    ;;
*)
    echo "usage: run.sh install|headers|cmake|pkgconfig|python BUILD SOURCE WORK LIBDIR" >&2
    exit 2
    ;;
esac
