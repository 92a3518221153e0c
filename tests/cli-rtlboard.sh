#!/usr/bin/env bash
# cli-rtlboard.sh ALBATROS — `albatros stream --sim=rtl`: the simulated board
# with the verilated reference RTL as its VP (firmware/sim/rtl_vp.h).  Clean
# streams whose RESULTs (the RTL's CRCs and cycles) match the emulator's, the
# cycles also against the golden vectors' expected.cycles (the cycle model's,
# stored); link faults recovered from as with the C-model board, with the
# same counts; a wrong bit in the frame store and an RTL built for other
# parameters caught; the messages for a board that is not built.  Builds the
# t32 and a256 boards once (rtl/board/build.sh, kept in BUILD/rtl-board/).
source "$(dirname "$0")/lib.sh"
top=$(cd "$(dirname "$0")/.." && pwd)
real=${ALBATROS_UNWRAPPED:-$bin}
build=$(cd "$(dirname "$real")" && pwd)
# under valgrind (make memcheck) the RTL runs some 30 times slower: one
# vector and two faults there, every one here
vectors=(shared-edges textured-far-plane sliver-box moving-lit) faults=(drop=6 truncate=7 truncate=3
         swap=4 duplicate=4 corrupt=3 corrupt-reply=30)
if [[ -n ${ALBATROS_UNWRAPPED:-} ]]; then vectors=(shared-edges) faults=(drop=6 truncate=7); fi

if ! command -v verilator > /dev/null; then
    echo "FAIL: verilator is not installed (the RTL board needs it; .ci/run installs it)" >&2
    echo "0 passed, 1 failed"
    exit 1
fi
for p in t32 a256; do
    if ALBATROS=$real ALB_LIB=$build/lib bash "$top/rtl/board/build.sh" "$build/rtl-board/$p" $p \
        2> "$tmp/build-$p.log"; then ok
    else bad "rtl/board/build.sh $p: $(cat "$tmp/build-$p.log")"; fi
done

# a clean stream of the built-in scene at t32: every RESULT from the RTL
expect 0 "stream: 4 frames to send to the RTL board" "$bin" stream --sim=rtl --profile t32
expect 0 "4 of 4 frames match the emulator" "$bin" stream --sim=rtl --profile t32
expect 0 "RTL board .*/rtl-board/t32/albatros-rtl-board.so: [1-9][0-9]* cycles clocked in .*cycles/s" \
    "$bin" stream --sim=rtl --profile t32
expect 0 '"rtl_board": \{"file": ".*albatros-rtl-board.so", "cycles": [1-9]' \
    "$bin" stream --sim=rtl --profile t32 --json
expect 0 "albatros-rtl: protocol 1, .* VP 32x32" "$bin" board info --sim=rtl --profile t32
# the same board named by its directory, and by its file
expect 0 "hardware agrees" "$bin" stream --sim=rtl --profile t32 --rtl-board "$build/rtl-board/t32"
expect 0 "hardware agrees" "$bin" stream --sim=rtl --profile t32 \
    --rtl-board "$build/rtl-board/t32/albatros-rtl-board.so"

# the RTL's cycles and CRCs against the cycle model's own events (not the
# timed model the host compares with): albatros vp --fidelity cycle --events
"$bin" gp --profile t32 -o "$tmp/b.stream" 2> /dev/null
"$bin" vp "$tmp/b.stream" --profile t32 --fidelity cycle --events "$tmp/ev.txt" -o "$tmp/f.exr" \
    > /dev/null 2>&1
"$bin" stream --sim=rtl --profile t32 --stream "$tmp/b.stream" --json > "$tmp/b.json" 2> /dev/null
want=$(awk '$2 == "frame" { sub(/^0x/, "", $5); printf "%s %s\n", $4, $5 }' "$tmp/ev.txt")
got=$(python3 -c '
import json, sys
for f in json.load(open(sys.argv[1]))["frames"]:
    print(f["board_cycles"], f["board_crc"])' "$tmp/b.json")
if [[ -n $want && $want == "$got" ]]; then ok
else bad "RTL board's cycles and CRCs (got: $got) differ from the cycle model's events ($want)"; fi
c0=$(head -n 1 <<<"$want" | cut -d' ' -f1)   # frame 0's cycles, for the planted mismatch below

# golden vectors at a256: the RTL board's cycles equal expected.cycles
for v in "${vectors[@]}"; do
    d=$top/test-vectors/$v
    # shellcheck disable=SC2046
    "$bin" stream --sim=rtl --stream "$d/expected.stream" $(cat "$d/options") --json \
        > "$tmp/$v.json" 2> "$tmp/$v.err"
    rc=$?
    want=$(sed -n 's/^frame=[0-9]* cycles=\([0-9]*\) .*/\1/p' "$d/expected.cycles")
    got=$(python3 -c '
import json, sys
for f in json.load(open(sys.argv[1]))["frames"]:
    print(f["board_cycles"])' "$tmp/$v.json" 2> /dev/null)
    if [[ $rc -eq 0 && -n $want && $want == "$got" ]]; then ok
    else bad "$v: exit $rc, RTL board cycles [$got], expected.cycles [$want]: $(cat "$tmp/$v.err")"; fi
done

# frames retiring a cycle apart (empty frames): a scan-out cut off, its CRC
# the board's resolve of the store, said on stderr, and still the emulator's
"$bin" gp "$top/rtl/bench/scenes/empty-frames.scene" --profile t32 -o "$tmp/e.stream" 2> /dev/null
expect 0 "rtl board: frame 0: the next frame retired before its scan-out ended: its CRC is the board's resolve" \
    "$bin" stream --sim=rtl --profile t32 --stream "$tmp/e.stream"
expect 0 "7 of 7 frames match the emulator" "$bin" stream --sim=rtl --profile t32 --stream "$tmp/e.stream"

# link faults: recovered from, and counted exactly as with the C-model board
for f in "${faults[@]}"; do
    counts() {
        "$bin" stream "$@" --profile t32 --wait 0 --fault $f --json 2> /dev/null | python3 -c '
import json, sys
j = json.load(sys.stdin)
print(j["result"], j["matched"], j["resumes"], j["queries"], j["board_errors"], j["host_crc_errors"])'
    }
    model=$(counts --sim) rtl=$(counts --sim=rtl)
    if [[ $rtl == "match 4 "* && $rtl == "$model" ]]; then ok
    else bad "--fault $f: RTL board [$rtl], C-model board [$model]"; fi
done
expect 0 "1 of 1 frames match .*1 resumes, 1 queries" \
    "$bin" stream --sim=rtl --profile t32 --wait 0 --fault truncate=3 "$top/rtl/bench/scenes/ties.scene"
expect 3 "the board stopped answering" "$bin" stream --sim=rtl --profile t32 --fault silence=1 --timeout 50

# planted bugs: a wrong bit in the frame store's RAM (the RTL's own scan-out
# and CRC see it; readback names the pixel), and an RTL built for other
# parameters (EDGE_UNITS 8 against the emulator's 3: the cycles differ)
expect 1 "frame 0: DIFFERS: CRC [0-9a-f]+ \(emulator [0-9a-f]+\), ([0-9]+) cycles \(emulator \1\)" \
    "$bin" stream --sim=rtl --profile t32 --fault flip=0
expect 1 "frame 2: first difference at pixel \([0-9]+, [0-9]+\) channel G" \
    "$bin" stream --sim=rtl --profile t32 --fault flip=2
expect 1 '"result": "differs"' "$bin" stream --sim=rtl --profile t32 --fault flip=0 --json
expect 1 "warning: --rtl-board .*EDGE_UNITS=8, the profile has EDGE_UNITS=3" \
    "$bin" stream --sim=rtl --profile t32 --set edge_units=3 --rtl-board "$build/rtl-board/t32"
# the same pixels; the RTL's cycles those of the cycle model at EDGE_UNITS 8
expect 1 "frame 0: DIFFERS: CRC ([0-9a-f]+) \(emulator \1\), $c0 cycles \(emulator [0-9]+\)" \
    "$bin" stream --sim=rtl --profile t32 --set edge_units=3 --rtl-board "$build/rtl-board/t32"
# --no-cycle-check (a real FPGA board, whose words come as USB delivers them):
# the same run matches on its CRCs, the cycles reported and not compared;
# a wrong pixel still fails it
expect 0 "frame 0: CRC ([0-9a-f]+) matches; $c0 cycles \(emulator [0-9]+, not compared" \
    "$bin" stream --sim=rtl --profile t32 --set edge_units=3 --rtl-board "$build/rtl-board/t32" \
    --no-cycle-check
expect 0 '"cycles_compared": false' "$bin" stream --sim=rtl --profile t32 --set edge_units=3 \
    --rtl-board "$build/rtl-board/t32" --no-cycle-check --json
expect 1 "frame 0: DIFFERS: CRC" "$bin" stream --sim=rtl --profile t32 --fault flip=0 --no-cycle-check

# a board that is not there, or not for this profile, is said so (exit 3:
# no board), with what to build
expect 3 "not built for this profile: it was built with EDGE_UNITS=8, the profile has EDGE_UNITS=3; build one with .make rtl-board PROFILE=t32" \
    "$bin" stream --sim=rtl --profile t32 --set edge_units=3
expect 3 "--rtl-board $tmp/none: .*No such file" "$bin" stream --sim=rtl --rtl-board "$tmp/none"
: > "$tmp/not.so"
expect 3 "cannot load the RTL board" "$bin" stream --sim=rtl --rtl-board "$tmp/not.so"
expect 2 "--sim=fpga: expected --sim, --sim=model .* or --sim=rtl" "$bin" stream --sim=fpga
expect 0 "hardware agrees" "$bin" stream --sim=model --profile t32
finish
