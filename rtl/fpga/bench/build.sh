#!/bin/sh
# build.sh — build (or reuse) the Verilator bench of alb_fpga_top
# (rtl/fpga/README.md, "The top's bench") for one profile:
#
#   [ALBATROS=build/albatros] [ALB_LIB=DIR] [ALB_FPGA_RTL=DIR]
#       rtl/fpga/bench/build.sh DIR PROFILE [--set KEY=VALUE ...]
#
# DIR/top_bench, linked with libalbatros from ALB_LIB (default
# TREE/build/lib).  The parameters are the profile's (rtl/profile-params.sh)
# and the FPGA build's own sizes, as rtl/fpga/fpga.sh gives them to yosys.
# ALB_FPGA_RTL names a folder holding the board's four files
# (alb_fpga_top.sv, alb_fx2_fifo.sv, alb_afifo.sv, alb_fpga_mem.sv) instead
# of rtl/fpga/: a planted bug (tests/fpga-top.sh --mutations).
# ALB_BENCH_LDFLAGS is added to the link, as in rtl/bench/verilate.sh.
# Rebuilt only when the parameters changed or a source is newer.
set -eu
[ $# -ge 2 ] || { echo "usage: build.sh DIR PROFILE [--set KEY=VALUE ...]" >&2; exit 2; }
dir=$1
shift
here=$(cd "$(dirname "$0")" && pwd)
fpga=$(dirname "$here")
rtl=$(dirname "$fpga")
top=$(dirname "$rtl")
lib=${ALB_LIB:-$top/build/lib}
board=${ALB_FPGA_RTL:-$fpga}
export ALBATROS=${ALBATROS:-$top/build/albatros}
command -v verilator > /dev/null || {
    echo "build.sh: verilator is not installed (Debian: apt-get install verilator)" >&2; exit 1; }
[ -e "$lib/libalbatros.so" ] && [ -e "$top/include/albatros/model.h" ] || {
    echo "build.sh: $lib/libalbatros.so is missing: build the library first (make)" >&2; exit 1; }
lib=$(realpath "$lib")
board=$(realpath "$board")
# the FPGA build's sizes, as rtl/fpga/fpga.sh gives them (rtl/fpga/board.sizes)
all=$("$rtl/profile-params.sh" --format shell --albatros "$ALBATROS" "$@"
      sed -e 's/#.*//' -e '/^ *$/d' "$fpga/board.sizes")
mkdir -p "$dir"
dir=$(realpath "$dir")
bench_ldflags=${ALB_BENCH_LDFLAGS:-}   # -fsanitize=... for a library built under them (make asan)
stamp=$(printf '%s\n' "$lib" "$board" "$bench_ldflags" "$all")
if [ -x "$dir/top_bench" ] && [ -f "$dir/params" ] && [ "$(cat "$dir/params")" = "$stamp" ] &&
   [ -z "$(find "$rtl" "$board" -newer "$dir/top_bench" \( -name '*.sv' -o -name '*.svh' -o \
           -name '*.cpp' -o -name '*.h' -o -name build.sh -o -name board.sizes \) 2>/dev/null)" ]; then
    exit 0
fi
rm -f "$dir/top_bench"
gflags=$(printf '%s\n' "$all" | sed 's/^/-G/')
echo "build.sh: verilating alb_fpga_top into $dir/top_bench (a minute or two)" >&2
# shellcheck disable=SC2046,SC2086
verilator --cc --exe --build -j 2 --trace -Wall -Wno-fatal --x-initial 0 \
    --top-module alb_fpga_top_tb -I"$rtl" -Mdir "$dir/obj" -o ../top_bench $gflags \
    -CFLAGS "-O1 -std=c++17 -Wno-unused -I$top/include" \
    -LDFLAGS "$bench_ldflags -L$lib -lalbatros -Wl,-rpath,$lib" \
    "$here/alb_fpga_top_tb.sv" "$board/alb_fpga_top.sv" "$board/alb_fx2_fifo.sv" \
    "$board/alb_afifo.sv" "$board/alb_fpga_mem.sv" \
    $(ls "$rtl"/alb_*.sv) "$here/top_bench.cpp" > "$dir/build.log" 2>&1 || {
    tail -30 "$dir/build.log" >&2
    echo "build.sh: the Verilator build failed; the whole log is $dir/build.log" >&2
    exit 1
}
printf '%s\n' "$stamp" > "$dir/params"
