#!/usr/bin/env bash
# fpga.sh [--build DIR] [--profile NAME] — alb_fpga_top (rtl/fpga/) for the
# iCEBreaker board, an iCE40 UP5K (docs/fpga.md): yosys synth_ice40, nextpnr-ice40
# (its --report JSON), icepack.  Outputs in DIR/fpga/: alb_fpga.bin (the
# bitstream), report.json (nextpnr's utilisation and Fmax), yosys.log and
# stat.txt (the cells yosys mapped, SB_RAM40_4K among them), pack-report.json (packed, utilisation only),
# nextpnr.log.
set -euo pipefail
build=build profile=up5k
while [[ $# -gt 0 ]]; do
    case $1 in
        --build) build=$2; shift 2 ;;
        --profile) profile=$2; shift 2 ;;
        *) echo "usage: fpga.sh [--build DIR] [--profile NAME]" >&2; exit 2 ;;
    esac
done
out=$build/fpga
mkdir -p "$out"
for tool in yosys nextpnr-ice40 icepack; do
    command -v $tool > /dev/null || { echo "fpga.sh: $tool is not installed (make setup)" >&2; exit 1; }
done
# The RTL's own sizes for this board (rtl/README.md): faces of up to six
# edges (a quad and its two bounding edges), 256 texels in four texture ids,
# 8-bit frame tags.
rtl_sizes="MAX_EDGES=6 TEX_WORDS=256 TEX_IDS=4 TAG_BITS=8"
chp=""
for kv in $(rtl/profile-params.sh --albatros "$build/albatros" --format shell "$profile") $rtl_sizes; do
    chp="$chp -chparam ${kv%%=*} ${kv#*=}"
done
clock_khz=$("$build/albatros" profiles "$profile" | sed -n 's/^clock_khz=//p')
rtl=(rtl/alb_fifo.sv rtl/alb_parser.sv rtl/alb_edge_store.sv rtl/alb_engine.sv
     rtl/alb_fill_queue.sv rtl/alb_fill.sv rtl/alb_pipe_reg.sv rtl/alb_pipe.sv
     rtl/alb_frame_store.sv rtl/alb_frame_crc.sv rtl/alb_vp.sv
     rtl/fpga/alb_afifo.sv rtl/fpga/alb_fx2_fifo.sv rtl/fpga/alb_fpga_mem.sv rtl/fpga/alb_fpga_top.sv)
echo "fpga.sh: yosys synth_ice40 ($profile)"
yosys -q -l "$out/yosys.log" -p "read_verilog -sv -defer -Irtl ${rtl[*]};
    hierarchy -top alb_fpga_top $chp;
    synth_ice40 -dsp -top alb_fpga_top -json $out/alb_fpga.json;
    tee -q -o $out/stat.txt stat" > /dev/null
echo "$clock_khz" > "$out/clock_khz"
pnr=(nextpnr-ice40 --up5k --package sg48 --pcf rtl/fpga/icebreaker.pcf --json "$out/alb_fpga.json")
rm -f "$out/report.json" "$out/alb_fpga.asc" "$out/alb_fpga.bin"
# packed only: the utilisation, whether or not it fits (no Fmax)
echo "fpga.sh: nextpnr-ice40 --up5k --package sg48 --pack-only"
"${pnr[@]}" --pack-only --report "$out/pack-report.json" -q -l "$out/pack.log"
if ! python3 rtl/fpga/fpga_report.py "$out/pack-report.json" > "$out/pack-verdict.txt" 2>&1; then
    cat "$out/pack-verdict.txt"
    echo "fpga.sh: $profile does not fit the UP5K (docs/fpga.md); no bitstream" >&2
    exit 1
fi
echo "fpga.sh: nextpnr-ice40 place and route (the VP's clock at $clock_khz kHz)"
# --timing-allow-fail: a missed clock is for fpga_report.py to judge and
# report, with the figure, not a bare failure here
"${pnr[@]}" --asc "$out/alb_fpga.asc" --report "$out/report.json" \
    --seed 1 --timing-allow-fail -q -l "$out/nextpnr.log"
icepack "$out/alb_fpga.asc" "$out/alb_fpga.bin"
echo "fpga.sh: $out/alb_fpga.bin, $out/report.json"
