#!/usr/bin/env bash
# sweep-unit.sh OUT UNIT [--noabc] NAME=VALUE ... — one job of the design-space
# view (docs/fpga.md, make fpga-sweep): yosys's generic synthesis of one RTL
# unit at the parameters alb_vp gives it for a profile (rtl/fpga/sweep_units.py),
# its memories kept as memories.  Writes OUT (one line):
#   unit=UNIT cells=N memory_bits=N memories=N seconds=N cpu_seconds=N abc=0|1
# cells: the gates, multiplexers and flip-flops of `synth` (ABC's -fast
# mapping unless --noabc) with memories not mapped to flip-flops
# (memory_map left out); memory_bits: what those memories hold (the
# reciprocal ROM, texture memory, the FIFO, tables the parser keeps), which
# a part puts in block RAM, not logic.  A result is cached by its unit,
# parameters and sources (OUT's directory/../cache), so a re-run is free.
set -euo pipefail
out=$1 unit=$2; shift 2
abc=1
if [ "${1:-}" = --noabc ]; then abc=0; shift; fi
here=$(cd "$(dirname "$0")" && pwd)
chp=$(python3 "$here/sweep_units.py" "$unit" "$@")
mapfile -t srcs < <(python3 -c 'import sys; sys.path.insert(0, sys.argv[1]); import sweep_units as s; print("\n".join(s.UNITS[sys.argv[2]]))' "$here" "$unit")
cache=$(dirname "$out")/../cache
mkdir -p "$cache" "$(dirname "$out")"
if [ "$abc" = 1 ]; then map="abc -fast; opt -fast"; else map=""; fi
flow="read_verilog -sv -Irtl ${srcs[*]};
    hierarchy -check -top $unit $chp; synth -top $unit -run begin:fine; flatten;
    select t:\\\$mem_v2; write_json @OUT@.mem.json; select -clear;
    opt -fast -full; opt -full; techmap; opt -fast; $map;
    check -assert; tee -q -o @OUT@.stat stat -json"
# the cache key: the unit, its parameters, the flow, the sources and yosys
key=$( { echo "$flow"; yosys -V; cat "${srcs[@]}" rtl/alb_defs.svh; } | sha1sum | cut -c1-16)
hit=$cache/$unit-$key
flow=${flow//@OUT@/$hit}
exec 9> "$hit.lock"
flock 9
if [ ! -s "$hit.line" ]; then
    cpu=$(mktemp)
    # synth's script (yosys help synth) with memory_map left out: the
    # memories stay $mem_v2 cells, counted as bits
    TIMEFORMAT='%R %U %S'
    if ! { time yosys -q -l "$hit.log" -p "$flow" > /dev/null 2>&3; } 3>&2 2> "$cpu"; then
        echo "sweep-unit.sh: yosys failed on $unit ($hit.log)" >&2
        rm -f "$cpu"
        exit 1
    fi
    # wall and CPU seconds (the machine may be shared)
    read -r wall user sys < "$cpu"
    rm -f "$cpu"
    secs=$(awk -v w="$wall" -v u="$user" -v s="$sys" 'BEGIN { printf "%d %d", w + 0.5, u + s + 0.5 }')
    # cells from the flattened unit's stat, memory bits from its \$mem_v2 cells
    python3 "$here/sweep_stat.py" "$hit.stat" "$hit.mem.json" "$unit" $secs "$abc" > "$hit.tmp"
    mv "$hit.tmp" "$hit.line"
fi
cp "$hit.line" "$out"
