#!/usr/bin/env bash
# mutations.sh — the bench catches bugs: each planted mutation of the RTL (a
# copy of rtl/, edited by sed) must make the Verilator bench fail, at the unit
# and event the bug belongs to.
#
#   rtl/bench/mutations.sh [--albatros BIN] [--dir DIR]
#
# Ends with "N of N mutations caught"; exit status 0 only if all were.
set -uo pipefail
albatros=build/albatros dir=
while [[ $# -gt 0 ]]; do
    case $1 in
        --albatros) albatros=$2; shift 2 ;;
        --dir) dir=$2; shift 2 ;;
        *) echo "usage: mutations.sh [--albatros BIN] [--dir DIR]" >&2; exit 2 ;;
    esac
done
here=$(cd "$(dirname "$0")" && pwd)
rtl=$(dirname "$here")
[[ -n $dir ]] || dir=$(mktemp -d)
mkdir -p "$dir"
albatros=$(realpath "$albatros")
# the mutants' benches link this tree's library and headers
export ALB_ROOT=$(dirname "$rtl") ALB_LIB=$(dirname "$albatros")/lib

# name | file | sed script | profile --set ... | scene | expected unit/event
# (classifier-off-by-one: a cell inside only if its least corner is >= 1,
# not >= 0 — every corner nonzero as well as none negative)
mutations=(
    "classifier-off-by-one|alb_engine.sv|s/lane_inside\[j\] = lane_v\[j\] \&\& !min_neg;/lane_inside[j] = lane_v[j] \&\& !min_neg \&\& h != 0 \&\& h_a != 0 \&\& h_b != 0 \&\& h_ab != 0;/||ties|engine/cell"
    "pipeline-stage-added|alb_pipe.sv|s/localparam int L = 1 + DIV_LAT + SHADE_LAT;/localparam int L = 2 + DIV_LAT + SHADE_LAT;/||random|pipe/write"
    "fifo-full-a-word-early|alb_fifo.sv|s/assign full = count == CW'(DEPTH);/assign full = count >= CW'(DEPTH - 1);/|--set fifo_depth=2|random|fifo/push"
    "tie-rule-flipped|alb_parser.sv|s/c = EW'(-(gamma <<< 1) - 64'sd1);/c = EW'(-(gamma <<< 1));/||ties|engine/cell"
    "equal-depth-wins|alb_pipe.sv|s/d != '0 \&\& d > zr_data/d != '0 \&\& d >= zr_data/||ties|pipe/write"
    "fill-column-major|alb_fill.sv|s/= c0 + (16'(i) \& ((16'd1 << wl) - 16'd1));/= c0 + 16'(iw >> wl);/;s/= r0 + 16'(iw >> wl);/= r0 + (16'(i) \& ((16'd1 << wl) - 16'd1));/||ties|pipe/write"
    "crc-byte-order|alb_frame_crc.sv|s/crc_after = crc_byte(crc_after, px\[39:32\]);/crc_after = crc_byte(crc_after, px[47:40]);/||ties|frame_crc/crc"
)

# the cases: a scene with ties, a random one
"$albatros" scene random --faces 30 --seed 7 -o "$dir/random.scene" > /dev/null 2>&1 || exit 2
cp "$here/scenes/ties.scene" "$dir/ties.scene"

caught=0 total=0
for m in "${mutations[@]}"; do
    IFS='|' read -r name file script sets scene expect <<< "$m"
    total=$((total + 1))
    work=$dir/$name
    rm -rf "$work"
    mkdir -p "$work"
    cp -r "$rtl" "$work/rtl"
    sed -i "$script" "$work/rtl/$file"
    if cmp -s "$rtl/$file" "$work/rtl/$file"; then
        echo "mutation $name: NOT APPLIED (the sed script matched nothing in $file)"
        continue
    fi
    # shellcheck disable=SC2086
    read -ra prof <<< "t32 $sets"
    width=$("$rtl/profile-params.sh" --albatros "$albatros" --format shell "${prof[@]}" | sed -n 's/^WIDTH=//p')
    mapfile -t params < <("$rtl/profile-params.sh" --albatros "$albatros" "${prof[@]}" \
                          --rtl SCAN_PIXELS=$((width / 4)))
    if ! bash "$work/rtl/bench/verilate.sh" "$work/model" "${params[@]}" > "$work/build.out" 2>&1; then
        echo "mutation $name: the mutant does not build"; tail -5 "$work/build.out"; continue
    fi
    "$albatros" gp "$dir/$scene.scene" --profile "${prof[@]}" -o "$work/s.stream" > /dev/null 2>&1 &&
        "$albatros" vp "$work/s.stream" --profile "${prof[@]}" --fidelity cycle \
            --events "$work/model.log" -q 2> "$work/vp.out" ||
        { echo "mutation $name: the model failed"; continue; }
    "$work/model/cosim" --events "$work/model.log" --stream "$work/s.stream" \
        --vcd "$work/divergence.vcd" --window 50 > "$work/cosim.out" 2>&1
    rc=$?
    line=$(grep -m1 '^cosim: divergence at' "$work/cosim.out" || true)
    got=$(sed -n 's/^cosim: divergence at cycle [0-9]*: unit \([a-z_]*\): event \([a-z]*\)$/\1\/\2/p' <<< "$line")
    if [[ $rc -eq 1 && $got == "$expect" && -s $work/divergence.vcd ]]; then
        caught=$((caught + 1))
        echo "mutation $name: caught, ${line#cosim: }"
    else
        echo "mutation $name: NOT CAUGHT as $expect (exit $rc; ${line:-no divergence})"
        sed 's/^/    /' "$work/cosim.out" | head -5
    fi
    rm -rf "$work/model/obj" "$work/model.log"
done
echo "$caught of $total mutations caught"
[[ $caught -eq $total ]]
