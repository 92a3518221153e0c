#!/usr/bin/env bash
# icarus.sh — run a scene or a word stream through the model and the RTL under
# Icarus Verilog (rtl/bench/tb_icarus.sv):
#
#   rtl/bench/icarus.sh [--albatros BIN] [--dir DIR] SCENE|STREAM PROFILE-ARGS...
#
# The GP's words as $readmemh text (albatros gp --memh, or converted here from
# a .stream), the push cycles, writes, frames and CRCs from the model's event
# log (albatros vp --fidelity cycle --events).  Ends with the bench's
# "icarus: PASS ..." line; exit status 0 only on PASS.
set -euo pipefail
albatros=build/albatros dir=
while [[ $# -gt 0 ]]; do
    case $1 in
        --albatros) albatros=$2; shift 2 ;;
        --dir) dir=$2; shift 2 ;;
        *) break ;;
    esac
done
[[ $# -ge 1 ]] || { echo "usage: icarus.sh [--albatros BIN] [--dir DIR] SCENE PROFILE-ARGS..." >&2; exit 2; }
scene=$1; shift
here=$(cd "$(dirname "$0")" && pwd)
rtl=$(dirname "$here")
[[ -n $dir ]] || dir=$(mktemp -d)
mkdir -p "$dir"

if [[ $scene == *.stream ]]; then   # one 8-digit hex word a line, from the little-endian file
    cp "$scene" "$dir/s.stream"
    od -An -v -tx4 -w4 "$dir/s.stream" | tr -d ' ' > "$dir/words.memh"
else
    "$albatros" gp "$scene" "$@" -o "$dir/s.stream" --memh "$dir/words.memh" > "$dir/gp.out" 2>&1
fi
"$albatros" vp "$dir/s.stream" "$@" --fidelity cycle --events "$dir/model.log" -q 2> "$dir/vp.out"
awk -v dir="$dir" '
    $2 == "push"  { printf "%08x\n", $1 > (dir "/pushes.memh"); nw++ }
    $2 == "write" { printf "%08x%04x%04x%08x%04x%04x%04x%08x%02x\n", $1, $3, $4, $5, $6, $7, $8, $9, $10 > (dir "/writes.memh"); nwr++ }
    $2 == "frame" { printf "%08x%02x%06x%08x%s\n", $1, 0, $3, $4, substr($5, 3) > (dir "/frames.memh"); nf++ }
    END { printf "+nwords=%d +nwrites=%d +nframes=%d\n", nw, nwr, nf > (dir "/counts") }
' "$dir/model.log"
touch "$dir/writes.memh" "$dir/frames.memh"
cmp -s <(awk '$2 == "push" { print substr($4, 3) }' "$dir/model.log") <(grep -v '^//' "$dir/words.memh") || {
    echo "icarus.sh: the model's pushes are not the stream's words" >&2; exit 1; }
width=$("$rtl/profile-params.sh" --albatros "$albatros" --format shell "$@" | sed -n 's/^WIDTH=//p')
mapfile -t params < <("$rtl/profile-params.sh" --albatros "$albatros" --format icarus \
                      --top tb_icarus "$@" --rtl SCAN_PIXELS=$(( width >= 4 ? width / 4 : 1 )))
iverilog -g2012 -I"$rtl" -s tb_icarus -o "$dir/tb.vvp" "${params[@]}" \
    "$rtl"/alb_*.sv "$here/alb_frame_mem.sv" "$here/tb_icarus.sv"
# shellcheck disable=SC2046
vvp -n "$dir/tb.vvp" +words="$dir/words.memh" +pushes="$dir/pushes.memh" \
    +writes="$dir/writes.memh" +frames="$dir/frames.memh" $(cat "$dir/counts") | tee "$dir/vvp.out"
grep -q '^icarus: PASS' "$dir/vvp.out"
