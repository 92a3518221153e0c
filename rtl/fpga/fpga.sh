#!/usr/bin/env bash
# fpga.sh [--build DIR] [--profile NAME] [--board BOARD] [--rtl NAME=VALUE ...] —
# alb_fpga_top (rtl/fpga/) for an iCE40 board (docs/fpga.md): yosys
# synth_ice40, nextpnr-ice40 (its --report JSON), icepack.  BOARD:
# hx8k-breakout (Lattice's iCE40HX8K-CT256 breakout board, the default: the
# build fits it) or icebreaker (iCE40UP5K-SG48, its DSPs used: 8% too
# small).  The RTL's own sizes are rtl/fpga/board.sizes; --rtl adds or
# overrides one (rtl/README.md), e.g. --rtl FOG_UNIT=1.  Outputs
# in DIR/fpga/: alb_fpga.bin (the bitstream), report.json (nextpnr's
# utilisation and Fmax), yosys.log and stat.txt (the cells yosys mapped,
# SB_RAM40_4K among them), pack-report.json (packed, utilisation only),
# nextpnr.log, flow.json (what was built: profile, board, part, sizes).
set -euo pipefail
build=build profile=up5k board=hx8k-breakout extra=()
usage() { echo "usage: fpga.sh [--build DIR] [--profile NAME] [--board icebreaker|hx8k-breakout] [--rtl NAME=VALUE ...]" >&2; exit 2; }
while [[ $# -gt 0 ]]; do
    case $1 in
        --build) build=$2; shift 2 ;;
        --profile) profile=$2; shift 2 ;;
        --board) board=$2; shift 2 ;;
        --rtl) [[ ${2:-} =~ ^[A-Z_]+=[0-9]+$ ]] || usage; extra+=("$2"); shift 2 ;;
        *) usage ;;
    esac
done
case $board in
    icebreaker)    part=iCE40UP5K-SG48 pnr_part=(--up5k --package sg48) dsp=-dsp
                   pcf=rtl/fpga/icebreaker.pcf led_low=1 ;;
    hx8k-breakout) part=iCE40HX8K-CT256 pnr_part=(--hx8k --package ct256) dsp=
                   pcf=rtl/fpga/hx8k-breakout.pcf led_low=0 ;;
    *) echo "fpga.sh: no board '$board' (icebreaker, hx8k-breakout)" >&2; exit 2 ;;
esac
out=$build/fpga
mkdir -p "$out"
for tool in yosys nextpnr-ice40 icepack; do
    command -v $tool > /dev/null || { echo "fpga.sh: $tool is not installed (make setup)" >&2; exit 1; }
done
# the RTL's own sizes for the board (rtl/fpga/board.sizes), then --rtl's
# shellcheck disable=SC2046,SC2116
rtl_sizes=$(echo $(sed -e 's/#.*//' rtl/fpga/board.sizes) "${extra[@]}" LED_LOW=$led_low)
chp=""
for kv in $(rtl/profile-params.sh --albatros "$build/albatros" --format shell "$profile") $rtl_sizes; do
    chp="$chp -chparam ${kv%%=*} ${kv#*=}"
done
clock_khz=$("$build/albatros" profiles "$profile" | sed -n 's/^clock_khz=//p')
rtl=(rtl/alb_fifo.sv rtl/alb_parser.sv rtl/alb_edge_store.sv rtl/alb_engine.sv
     rtl/alb_fill_queue.sv rtl/alb_fill.sv rtl/alb_pipe_reg.sv rtl/alb_pipe.sv
     rtl/alb_frame_store.sv rtl/alb_frame_crc.sv rtl/alb_vp.sv
     rtl/fpga/alb_afifo.sv rtl/fpga/alb_fx2_fifo.sv rtl/fpga/alb_fpga_mem.sv rtl/fpga/alb_fpga_top.sv)
echo "fpga.sh: yosys synth_ice40 $dsp ($profile, $board: $part)"
yosys -q -l "$out/yosys.log" -p "read_verilog -sv -defer -Irtl ${rtl[*]};
    hierarchy -top alb_fpga_top $chp;
    synth_ice40 $dsp -top alb_fpga_top -json $out/alb_fpga.json;
    tee -q -o $out/stat.txt stat" > /dev/null
echo "$clock_khz" > "$out/clock_khz"
printf '{"profile": "%s", "clock_khz": %s, "board": "%s", "part": "%s", "rtl": "%s"}\n' \
    "$profile" "$clock_khz" "$board" "$part" "$rtl_sizes" > "$out/flow.json"
pnr=(nextpnr-ice40 "${pnr_part[@]}" --pcf "$pcf" --json "$out/alb_fpga.json")
rm -f "$out/report.json" "$out/alb_fpga.asc" "$out/alb_fpga.bin"
# packed only: the utilisation, whether or not it fits (no Fmax)
echo "fpga.sh: nextpnr-ice40 ${pnr_part[*]} --pack-only"
"${pnr[@]}" --pack-only --report "$out/pack-report.json" -q -l "$out/pack.log"
if ! python3 rtl/fpga/fpga_report.py "$out/pack-report.json" > "$out/pack-verdict.txt" 2>&1; then
    cat "$out/pack-verdict.txt"
    echo "fpga.sh: $profile does not fit the $part (docs/fpga.md); no bitstream" >&2
    exit 1
fi
echo "fpga.sh: nextpnr-ice40 place and route (the VP's clock at $clock_khz kHz)"
# --timing-allow-fail: a missed clock is for fpga_report.py to judge and
# report, with the figure, not a bare failure here
"${pnr[@]}" --asc "$out/alb_fpga.asc" --report "$out/report.json" \
    --seed 1 --timing-allow-fail -q -l "$out/nextpnr.log"
icepack "$out/alb_fpga.asc" "$out/alb_fpga.bin"
echo "fpga.sh: $out/alb_fpga.bin, $out/report.json"
