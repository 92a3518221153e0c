#!/bin/sh
# verilate.sh — build (or reuse) the Verilator bench for one parameter set:
#
#   [ALB_ROOT=TREE] [ALB_LIB=DIR] rtl/bench/verilate.sh DIR [-GNAME=VALUE ...]
#
# DIR/cosim is the bench (rtl/bench/cosim.cpp over rtl/ and the memory model),
# linked with libalbatros from ALB_LIB (default TREE/build/lib) and its headers
# from TREE/include (TREE: the tree holding this rtl/, or ALB_ROOT for a copy
# of rtl/ elsewhere); it is rebuilt only when the parameters changed or a
# source is newer, so a parameter set costs one Verilator build per change of
# the RTL.  ALB_BENCH_LDFLAGS is added to the link (tests/cosim.sh gives it
# -fsanitize=... when the library was built under the sanitizers, whose
# runtime must come first in the program).
set -eu
[ $# -ge 1 ] || { echo "usage: verilate.sh DIR [-GNAME=VALUE ...]" >&2; exit 2; }
dir=$1
shift
here=$(cd "$(dirname "$0")" && pwd)
rtl=$(dirname "$here")
top=${ALB_ROOT:-$(dirname "$rtl")}
lib=${ALB_LIB:-$top/build/lib}
[ -e "$lib/libalbatros.so" ] && [ -e "$top/include/albatros/model.h" ] || {
    echo "verilate.sh: $lib/libalbatros.so or $top/include/albatros/model.h is missing:" \
         "build the library first (make), or set ALB_ROOT and ALB_LIB" >&2; exit 1; }
lib=$(realpath "$lib")
mkdir -p "$dir"
bench_ldflags=${ALB_BENCH_LDFLAGS:-}
params=$(printf '%s\n' "$lib" "$bench_ldflags" "$@")
if [ -x "$dir/cosim" ] && [ -f "$dir/params" ] && [ "$(cat "$dir/params")" = "$params" ] &&
   [ -z "$(find "$rtl" "$here" -newer "$dir/cosim" \( -name '*.sv' -o -name '*.svh' -o \
           -name '*.cpp' -o -name '*.h' -o -name verilate.sh \) 2>/dev/null)" ]; then
    exit 0
fi
rm -f "$dir/cosim"
printf '%s\n' "$params" > "$dir/params"
# shellcheck disable=SC2046
verilator --cc --exe --build -j 2 --trace -Wall -Wno-fatal --top-module alb_bench_top \
    -I"$rtl" -I"$here" -Mdir "$dir/obj" -o ../cosim "$@" \
    -CFLAGS "-O1 -std=c++17 -Wno-unused -I$top/include" \
    -LDFLAGS "$bench_ldflags -L$lib -lalbatros -Wl,-rpath,$lib" \
    "$here/alb_bench_top.sv" "$here/alb_frame_mem.sv" $(ls "$rtl"/alb_*.sv) \
    "$here/cosim.cpp" "$here/events.cpp" "$here/scoreboard.cpp" > "$dir/build.log" 2>&1 || {
    tail -30 "$dir/build.log" >&2
    echo "verilate.sh: the Verilator build failed; the whole log is $dir/build.log" >&2
    exit 1
}
