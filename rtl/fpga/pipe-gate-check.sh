#!/usr/bin/env bash
# pipe-gate-check.sh [CYCLES] — alb_pipe's synth_ice40 -dsp netlist at the up5k
# widths simulated beside the RTL (Icarus, yosys's ice40/cells_sim.v), every
# output compared every cycle on random samples, set-ups and depth-store
# answers (rtl/fpga/pipe_gate_tb.sv).  The cosim sees the RTL only; this sees
# what yosys made of it (docs/fpga.md, "yosys 0.23 and the DSPs").  A few
# minutes; not part of make test.
set -euo pipefail
cycles=${1:-1500}
out=build/fpga-gate
mkdir -p "$out"
cells=$(dirname "$(command -v yosys)")/../share/yosys/ice40/cells_sim.v
[[ -e $cells ]] || cells=/usr/share/yosys/ice40/cells_sim.v
chp=""
for kv in RATE=1 LW=4 LH=4 CB=8 DB=16 COLB=4 RB=8 FI=8 DIV_LAT=4 SHADE_LAT=4 TEX_WORDS=256 ZR_REG=1; do
    chp="$chp -chparam ${kv%%=*} ${kv#*=}"
done
yosys -q -l "$out/yosys.log" -p "read_verilog -sv -defer -Irtl rtl/alb_pipe_reg.sv rtl/alb_pipe.sv;
    hierarchy -top alb_pipe $chp; synth_ice40 -dsp -top alb_pipe; rename alb_pipe alb_pipe_gate;
    write_verilog -noattr $out/gate.v; tee -q -o $out/stat.txt stat" > /dev/null
iverilog -g2012 -DNO_ICE40_DEFAULT_ASSIGNMENTS -Irtl -DCYCLES="$cycles" -o "$out/tb.vvp" \
    rtl/fpga/pipe_gate_tb.sv rtl/alb_pipe_reg.sv rtl/alb_pipe.sv "$out/gate.v" "$cells" 2> "$out/iverilog.log" ||
    { cat "$out/iverilog.log" >&2; exit 1; }
vvp -n "$out/tb.vvp" | tee "$out/sim.txt"
grep -q ', 0 mismatches' "$out/sim.txt"
