#!/usr/bin/env bash
# sweep-point.sh BUILD NAME PROFILE [--set k=v ...] — one point of the
# design-space view (docs/fpga.md, make fpga-sweep): yosys's generic
# synthesis of alb_vp for that member, cells per unit (hierarchy kept,
# -noabc: the gates techmap makes, before ABC's optimisation), beside the
# cycle model's cycles per frame on the built-in scene and two stress
# families.  Excluded from the synthesis, as memories a RAM would hold: the
# reciprocal ROM (recip_bits 8 here), texture memory (64 texels), the FIFO
# (4 words).  Writes BUILD/fpga-sweep/NAME.csv (one row, no header).
set -euo pipefail
build=$1 name=$2 profile=$3; shift 3
out=$build/fpga-sweep
mkdir -p "$out"
bin=$build/albatros
sets=("$@")
chp=""
for kv in $(rtl/profile-params.sh --albatros "$bin" --format shell "$profile" "${sets[@]}" \
            --set recip_bits=8 --set fifo_depth=4) TEX_WORDS=64; do
    chp="$chp -chparam ${kv%%=*} ${kv#*=}"
done
rtl=(rtl/alb_fifo.sv rtl/alb_parser.sv rtl/alb_edge_store.sv rtl/alb_engine.sv
     rtl/alb_fill_queue.sv rtl/alb_fill.sv rtl/alb_pipe_reg.sv rtl/alb_pipe.sv
     rtl/alb_frame_store.sv rtl/alb_frame_crc.sv rtl/alb_vp.sv)
yosys -q -l "$out/$name.log" -p "read_verilog -sv -defer -Irtl ${rtl[*]};
    hierarchy -top alb_vp $chp; synth -top alb_vp -noabc;
    tee -q -o $out/$name.stat stat" > /dev/null
# cells per unit: a module's own cells (its submodules counted as theirs)
units=$(awk '
    /^=== / { m = $2; sub(/^\$paramod\$[0-9a-f]*\\/, "", m); sub(/^\$paramod\\/, "", m);
              sub(/\\.*/, "", m); next }
    /^=== design hierarchy ===/ { m = "" }
    m != "" && /Number of cells:/ { c[m] += $4 }
    END { printf "%d,%d,%d,%d,%d,%d,%d,%d,%d", c["alb_parser"], c["alb_edge_store"], c["alb_engine"],
          c["alb_fill_queue"], c["alb_fill"], c["alb_pipe"] + c["alb_pipe_reg"],
          c["alb_frame_store"], c["alb_frame_crc"], c["alb_fifo"] + c["alb_vp"] }' "$out/$name.stat")
total=$(echo "$units" | tr ',' '\n' | awk '{ s += $1 } END { print s }')
# cycles per frame, the mean over a run's frames
cycles() {   # INPUT...
    "$bin" render "$@" --profile "$profile" "${sets[@]}" --fidelity cycle --json 2> /dev/null |
        python3 -c 'import json,sys; f=json.load(sys.stdin)["frames"]; print(round(sum(x["timing"]["cycles"] for x in f)/len(f)))'
}
builtin=$(cycles)
"$bin" scene interpenetrating --severity 0.5 -o "$out/$name.many.scene" > /dev/null 2>&1
"$bin" scene deep --severity 0.5 -o "$out/$name.slivers.scene" > /dev/null 2>&1
many=$(cycles "$out/$name.many.scene")
sliv=$(cycles "$out/$name.slivers.scene")
echo "$name,$profile ${sets[*]//--set /},$total,$units,$builtin,$many,$sliv" > "$out/$name.csv"
