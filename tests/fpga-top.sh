#!/usr/bin/env bash
# fpga-top.sh [BUILD] [--mutations] — the FPGA top (rtl/fpga/alb_fpga_top.sv)
# simulated with the FX2's side of the board (rtl/fpga/bench/, rtl/fpga/README.md):
# every RESULT record against the C model stepped beside the VP (in the
# bench) and against the CRCs of `albatros stream --sim` and the stream's
# FRAME_END counts (here); the built-in scene's refused TEXTURE as the error
# record; RESUME and RESET; two IFCLKs against the VP's 12 MHz.  Known
# failures of the top are marked: each must fail as written down, and a mark
# whose case passes fails the run (remove it).  --mutations: planted bugs in
# copies of rtl/fpga/, each of which a case must catch (make fpga-top).
# Ends with "N passed, N failed".
set -u
build=build mutations=0
for a in "$@"; do
    case $a in
        --mutations) mutations=1 ;;
        -*) echo "usage: fpga-top.sh [BUILD] [--mutations]" >&2; exit 2 ;;
        *) build=$a ;;
    esac
done
bin=$build/albatros
out=$build/fpga-top
export ALB_LIB=$build/lib ALBATROS=$bin
# a library built under ASan/UBSan (make asan) needs their runtime first in
# the bench (as tests/cosim.sh does it)
if ldd "$build/lib/libalbatros.so" 2>/dev/null | grep -q 'libasan'; then
    export ALB_BENCH_LDFLAGS="-fsanitize=address,undefined"
fi
mkdir -p "$out"
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; [[ -n ${2:-} ]] && sed 's/^/     /' "$2" | tail -n 12; }
finish() { echo "$pass passed, $fail failed"; [[ $fail -eq 0 && $pass -gt 0 ]]; exit; }

command -v verilator > /dev/null || { bad "verilator is not installed (make setup)"; finish; }
[[ -x $bin ]] || { bad "$bin is missing: build it with make"; finish; }
if ! bash rtl/fpga/bench/build.sh "$out/bench" up5k > "$out/build.out" 2>&1; then
    bad "the bench does not build" "$out/build.out"; finish
fi
bench=$out/bench/top_bench

# ---- the streams and what each record must say, from the CLI ----

scene=rtl/fpga/bench/quads.scene
# the drawing case: no textures, no face of more than four vertices (the FPGA
# build's MAX_EDGES 6: four edges and two bounding edges)
if awk '$1 == "f" { n = 0; for (i = 2; i <= NF && $i ~ /^[0-9]+$/; i++) n++; if (n > 4) bad = 1 }
        $1 == "texture" { bad = 1 } END { exit bad }' "$scene"; then
    ok "$scene: faces of at most 4 vertices, no texture"
else
    bad "$scene: a face of more than 4 vertices, or a texture"
fi
"$bin" gp --profile up5k "$scene" -o "$out/quads.stream" > /dev/null 2>&1 &&
    "$bin" dump "$out/quads.stream" > "$out/quads.dump" 2>&1 ||
    { bad "albatros gp/dump of $scene" "$out/quads.dump"; finish; }
max_edges=$(sed -n 's/.* FACE edges=\([0-9]*\).*/\1/p' "$out/quads.dump" | sort -n | tail -n 1)
if [[ -n $max_edges && $max_edges -le 6 ]]; then
    ok "quads.stream: faces of at most $max_edges edges (MAX_EDGES 6)"
else
    bad "quads.stream: a face of ${max_edges:-?} edges, beyond MAX_EDGES 6"
fi
# frame number, CRC (the host's, of its emulator's frame) and faces
# (FRAME_END's count), one line a frame
"$bin" stream --sim --stream "$out/quads.stream" --profile up5k --json > "$out/quads.json" 2>&1
python3 - "$out/quads.json" "$out/quads.dump" > "$out/quads.want" <<'EOF' ||
import json, re, sys
frames = json.load(open(sys.argv[1]))["frames"]
faces = [int(m.group(1)) for m in re.finditer(r"FRAME_END faces=(\d+)", open(sys.argv[2]).read())]
assert len(frames) == len(faces) > 0
for f, n in zip(frames, faces):
    print(f["frame"], f["crc"], n)
EOF
    { bad "the CLI's CRCs for quads.stream" "$out/quads.json"; finish; }
nframes=$(wc -l < "$out/quads.want")

"$bin" gp --profile up5k -o "$out/builtin.stream" > /dev/null 2>&1 &&
    "$bin" dump "$out/builtin.stream" > "$out/builtin.dump" 2>&1 ||
    { bad "albatros gp/dump of the built-in scene" "$out/builtin.dump"; finish; }
# the build has no texture unit (rtl/fpga/board.sizes): the first TEXTURE
# is refused, E_UNIT (17, rtl/README.md), at its header's word offset
tex_at=$(awk '/ TEXTURE / { print $1; exit }' "$out/builtin.dump")
tex_word=${tex_at:+$((16#$tex_at / 4))}

# ---- the cases ----

# records FILE WANT [RESUMED]: every RESULT's frame, CRC and faces as the CLI
# says, each frame of the stream reported (a frame resent after a restart may
# come twice)
records_ok() {
    python3 - "$1" "$2" <<'EOF'
import sys
want = {}
for line in open(sys.argv[2]):
    n, crc, faces = line.split()
    want[int(n)] = (crc, int(faces))
seen = set()
bad = 0
for line in open(sys.argv[1]):
    f = line.split()
    if f[0] != "result":
        print("not a RESULT:", line.strip()); bad = 1; continue
    n, crc, faces = int(f[2]), f[3], int(f[5])
    if want.get(n) != (crc, faces):
        print("frame %d: CRC %s, %d faces; the CLI's %s" % (n, crc, faces, want.get(n))); bad = 1
    seen.add(n)
missing = sorted(set(want) - seen)
if missing:
    print("no RESULT for frames", missing); bad = 1
sys.exit(bad)
EOF
}

# run NAME RECORD-CHECK BENCH-ARGS...: the bench passes, and its records pass
# the check (records_ok against quads.want, or a pattern for the error case)
run() {
    local name=$1 check=$2; shift 2
    local log=$out/$name.log rec=$out/$name.rec
    if ! "$bench" --records "$rec" "$@" > "$log" 2>&1; then
        bad "$name: the bench fails" "$log"; return
    fi
    if [[ $check == records ]]; then
        if ! records_ok "$rec" "$out/quads.want" >> "$log" 2>&1; then
            bad "$name: the records against the CLI" "$log"; return
        fi
    elif ! grep -qxE "$check" "$rec"; then
        bad "$name: records are not /$check/" "$rec"; return
    fi
    ok "$name: $(tail -n 1 "$log" | sed 's/^top_bench: //')"
}

# known NAME PATTERN BENCH-ARGS...: a known failure of the top: the bench must
# fail, saying PATTERN
known() {
    local name=$1 pat=$2; shift 2
    local log=$out/$name.log
    if "$bench" --quiet "$@" > "$log" 2>&1; then
        bad "$name: known failure passes now: remove its mark in tests/fpga-top.sh" "$log"
    elif grep -qE -- "$pat" "$log"; then
        ok "$name: known failure: $(grep -m 1 -E -- "$pat" "$log" | sed 's/^top_bench: FAIL: //')"
    else
        bad "$name: fails, but not as known (/$pat/)" "$log"
    fi
}

q=$out/quads.stream
run draw-48mhz records --stream "$q" --seed 1 --phase-ps 7001
run draw-30mhz records --stream "$q" --seed 2 --ifclk-khz 30000 --phase-ps 12345
# the EP8 flow control met: the summary counts the clocks EP8 was full
for n in draw-48mhz draw-30mhz; do
    full=$(sed -n 's/.*EP8 full \([0-9]*\) times.*/\1/p' "$out/$n.log")
    if [[ ${full:-0} -ge 2 ]]; then ok "$n: EP8 went full $full times (FLAGB)"
    else bad "$n: EP8 went full ${full:-0} times: the back-pressure is not exercised"; fi
done
if [[ -n $tex_word ]]; then
    run builtin-no-tex "error 0 $tex_word" --stream "$out/builtin.stream" \
        --expect-error "$tex_word:17"
else
    bad "the built-in scene has no TEXTURE (E_UNIT expected)"
fi
# a RESUME late in the stream (the host resends from the first frame without
# a RESULT: the CONFIG replayed, then a FRAME), a RESET (the whole stream again)
run resume-late records --stream "$q" --seed 3 --resume 1000
run reset records --stream "$q" --seed 4 --reset 900

# what the bench found in the top, now mended (rtl/fpga/README.md): a RESUME
# within the first frames after a reset (stale depths whose tags the new
# frames repeat: the top clears the frame store after every reset), a restart
# in the middle of a record (the record goes out whole), the stream from
# power-up without a host RESET (the IFCLK side's own power-up reset), a flag
# a clock later than the FX2's datasheet has it (a clock of margin)
run resume-early records --stream "$q" --seed 5 --resume 300
run restart-in-record records --stream "$q" --seed 6 --restart-in-record 5
if grep -q ', 1 records across one)' "$out/restart-in-record.log"; then
    ok "restart-in-record: the record the restart cut into went out whole"
else
    bad "restart-in-record: no record across the restart" "$out/restart-in-record.log"
fi
run power-up records --stream "$q" --seed 7 --power-up --max-cycles 100000
run flag-lag-1 records --stream "$q" --seed 8 --flag-lag 1
known flag-lag-2 "SLRD while EP4 is empty" --stream "$q" --flag-lag 2

# ---- planted bugs: each in a copy of rtl/fpga/, caught by a case ----

if ((mutations)); then
    # name | file | sed script | the failure expected
    muts=(
        "record-crc-beats-swapped|alb_fpga_top.sv|s/res_cycles, ev_crc_value, 8'd0, res_frame}/res_cycles, ev_crc_value[15:0], ev_crc_value[31:16], 8'd0, res_frame}/|u32 1 \(CRC\)"
        "record-crc-byte-order|alb_fpga_top.sv|s/res_cycles, ev_crc_value, 8'd0, res_frame}/res_cycles, ev_crc_value[7:0], ev_crc_value[15:8], ev_crc_value[23:16], ev_crc_value[31:24], 8'd0, res_frame}/|u32 1 \(CRC\)"
        "record-cycles-words-swapped|alb_fpga_top.sv|s/res_faces, res_cycles, ev_crc_value/res_faces, res_cycles[31:0], res_cycles[63:32], ev_crc_value/|u32 2 \(cycles low\)"
        "record-beats-swapped|alb_fpga_top.sv|s/if (out_beat == 4'(i))/if (out_beat == 4'(i ^ 1))/|u32 0 \(frame\)"
        "record-no-last-beat|alb_fpga_top.sv|s/assign r_in = {out_left == 4'd1, beat};/assign r_in = {out_left == 4'd0, beat};/|record of|RESULTs owed"
        "ep4-flag-a-clock-early|alb_fx2_fifo.sv|/half <= !half;/,/wait_n <= 2'd2;/s/wait_n <= 2'd2;/wait_n <= 2'd0;/|SLRD while EP4 is empty"
        "no-pktend|alb_fx2_fifo.sv|s/pe_n <= 1'b0; /pe_n <= 1'b1; /|RESULTs owed"
        "words-fifo-never-full|alb_afifo.sv|s/assign full = (wbin\[A\] != rbin_w\[A\])/assign full = 1'b0 \&\& (wbin[A] != rbin_w[A])/|the VP takes"
        "no-config-replay|alb_fpga_top.sv|s/wire replay = cfg_given < cfg_kept;/wire replay = 1'b0;/|the VP takes f0"
        "no-clear-after-reset|alb_fpga_top.sv|s/wire clearing = !clr_n\[AW\];/wire clearing = 1'b0;/|u32 1 \(CRC\)"
        "records-fifo-reset-by-restart|alb_fpga_top.sv|s/\.wclk(clk_vp), \.wrst(pwr_vp)/.wclk(clk_vp), .wrst(rst_vp)/|record of|RESULT"
        "no-ifclk-power-up-reset|alb_fpga_top.sv|s/wire pwr_if = por_if != 4'hF; /wire pwr_if = 1'b0; /|words taken"
    )
    for m in "${muts[@]}"; do
        IFS='|' read -r name file script pat pat2 <<< "$m"
        work=$out/mut-$name
        rm -rf "$work"
        mkdir -p "$work/rtl"
        cp rtl/fpga/alb_fpga_top.sv rtl/fpga/alb_fx2_fifo.sv rtl/fpga/alb_afifo.sv \
           rtl/fpga/alb_fpga_mem.sv "$work/rtl/"
        sed -i "$script" "$work/rtl/$file"
        if cmp -s "rtl/fpga/$file" "$work/rtl/$file"; then
            bad "mutation $name: NOT APPLIED (the sed script matched nothing in $file)"; continue
        fi
        if ! ALB_FPGA_RTL=$work/rtl bash rtl/fpga/bench/build.sh "$work/bench" up5k \
            > "$work/build.out" 2>&1; then
            bad "mutation $name: the mutant does not build" "$work/build.out"; continue
        fi
        caught=""
        for c in "draw --stream $q --seed 1" "resume --stream $q --seed 3 --resume 1000" \
                 "resume-early --stream $q --seed 5 --resume 300" \
                 "in-record --stream $q --seed 6 --restart-in-record 5" \
                 "power-up --stream $q --seed 7 --power-up --max-cycles 100000"; do
            read -ra args <<< "${c#* }"
            "$work/bench/top_bench" --quiet "${args[@]}" > "$work/${c%% *}.log" 2>&1 &&
                continue
            if grep -qE -- "$pat" "$work/${c%% *}.log" ||
               { [[ -n $pat2 ]] && grep -qE -- "$pat2" "$work/${c%% *}.log"; }; then
                caught="${c%% *}: $(grep -m 1 'FAIL' "$work/${c%% *}.log" | sed 's/^top_bench: FAIL: //')"
                break
            fi
            caught="x"
            bad "mutation $name: the ${c%% *} case fails, but not with /$pat/" "$work/${c%% *}.log"
            break
        done
        if [[ -z $caught ]]; then bad "mutation $name: NOT CAUGHT (every case passes)"
        elif [[ $caught != x ]]; then ok "mutation $name caught ($caught)"; fi
    done
fi
finish
