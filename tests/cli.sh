#!/usr/bin/env bash
# cli.sh ALBATROS — the command line as a user meets it: help, errors with
# their exit status and message, and the files each subcommand writes.
source "$(dirname "$0")/lib.sh"

expect 0 'usage: albatros SUBCOMMAND' "$bin" --help
expect 0 '^albatros [0-9]+\.[0-9]+\.[0-9]+$' "$bin" --version
expect 2 "unknown subcommand 'frobnicate'" "$bin" frobnicate
expect 2 'usage' "$bin"
for sub in gp dump vectors render vp reference compare accuracy scene; do
    expect 0 "usage: albatros $sub" "$bin" $sub --help
done
expect 0 'profile=a1024' "$bin" profiles
# --version on every subcommand, as on the top level
for sub in $("$bin" --help | sed -n 's/^  \([a-z]*\)  .*/\1/p'); do
    expect 0 "^albatros [0-9]+\.[0-9]+\.[0-9]+$" "$bin" $sub --version
done
expect 0 "^albatros [0-9]+\.[0-9]+\.[0-9]+$" "$bin" render --profile t32 --version

# gp on the built-in scene: binary stream, hex dump, JSON
expect 0 'faces:' "$bin" gp -o "$tmp/b.stream" --hex "$tmp/b.hex"
[[ -s $tmp/b.stream && $(( $(stat -c %s "$tmp/b.stream") % 4 )) -eq 0 ]] && ok || bad "stream size"
grep -q 'CONFIG version=1' "$tmp/b.hex" && grep -q 'edge\[0\] U=' "$tmp/b.hex" && ok || bad "hex dump fields"
expect 0 '"faces_out": [0-9]+' "$bin" gp --json
# the same input gives the same bytes
"$bin" gp -q -o "$tmp/b2.stream" && cmp -s "$tmp/b.stream" "$tmp/b2.stream" && ok || bad "gp not deterministic"
# dump reads it back; its listing equals gp's
"$bin" dump "$tmp/b.stream" > "$tmp/d.hex" 2>&1 && cmp -s "$tmp/b.hex" "$tmp/d.hex" && ok || bad "dump != gp --hex"

# errors: options, profiles, files
expect 2 "nothing to write" "$bin" gp
expect 2 "unknown option '--frob'" "$bin" gp --frob
expect 2 "option '--hex' needs a value" "$bin" gp --hex
expect 2 "unknown profile" "$bin" gp --json --profile nope
expect 2 "unknown profile key" "$bin" gp --json --set nope=1
expect 2 "powers of two" "$bin" gp --json --set width=500
expect 2 "expected three numbers" "$bin" gp --json --eye 1,2
expect 1 "nope.scene: error: cannot open scene" "$bin" gp --json nope.scene
printf 'albatros-scene 1\nobject t\n v 0 0 5\n v 1 0 5\n v 2 0 5\n f 1 2 3\nend\n' > "$tmp/line.scene"
expect 1 "line.scene:6:2: error: face 0 of object 't' has zero area" "$bin" gp --json "$tmp/line.scene"
printf 'albatros-scene 1\nnear x\n' > "$tmp/bad.scene"
expect 1 "bad.scene:2:6: error: expected a number, found 'x'" "$bin" gp --json "$tmp/bad.scene"

# dump rejects malformed streams, naming the offset
head -c 6 "$tmp/b.stream" > "$tmp/odd.stream"
expect 1 "offset 4: error: file length 6 is not a whole number" "$bin" dump "$tmp/odd.stream"
head -c 400 "$tmp/b.stream" > "$tmp/trunc.stream"
expect 1 "stream truncated inside|without an END" "$bin" dump "$tmp/trunc.stream"
printf '\x00\x00\x00\x12' > "$tmp/op.stream"
expect 1 "offset 0: error: word 0: 0x12000000 is not a packet opcode" "$bin" dump "$tmp/op.stream"
expect 1 "cannot open" "$bin" dump "$tmp/none.stream"

# vectors: a broken expected stream is reported with the word and its fields
mkdir -p "$tmp/v/tri"
printf 'albatros-scene 1\nobserver fov 90\nobject t\n v 0 0 5\n v 1 0 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/v/tri/scene.scene"
echo "a triangle" > "$tmp/v/tri/README"
echo "--profile a256" > "$tmp/v/tri/options"
expect 0 "created tri" "$bin" vectors bless "$tmp/v"
expect 0 "1 passed, 0 failed" "$bin" vectors check "$tmp/v"
printf '\x01' | dd of="$tmp/v/tri/expected.stream" bs=1 seek=48 conv=notrunc 2>/dev/null
expect 1 "expected .* depth[.]A=" "$bin" vectors check "$tmp/v"
# a changed colour: the stream and the frame differ; the pixel and channel are named
"$bin" vectors bless "$tmp/v" >/dev/null
cp "$tmp/v/tri/expected.cycles" "$tmp/cycles.bak"
sed -i 's/engine_busy=[0-9]*/engine_busy=1/' "$tmp/v/tri/expected.cycles"
expect 1 "frame 0 counters differ: expected engine_busy=1, got engine_busy=" "$bin" vectors check "$tmp/v"
cp "$tmp/cycles.bak" "$tmp/v/tri/expected.cycles"
sed -i 's/^ f 1 2 3$/ f 1 2 3 colour 10 20 30/' "$tmp/v/tri/scene.scene"
expect 1 "frame 0 differs at pixel \([0-9]+, [0-9]+\): vp.R expected 200, got 10" \
    "$bin" vectors check --diff-dir "$tmp/diffs" "$tmp/v"
[[ -s $tmp/diffs/tri.0000.png ]] && ok || bad "no diff image"
echo "flipped on purpose" > "$tmp/v/tri/KNOWN-FAILURE"
expect 0 "known failure tri" "$bin" vectors check "$tmp/v"
expect 1 "no vector named 'zzz'" "$bin" vectors check "$tmp/v" zzz
rm "$tmp/v/tri/KNOWN-FAILURE"
"$bin" vectors bless "$tmp/v" >/dev/null
# frames by digest (what the musl build of make crosscheck checks with): the
# digests of the expected EXR files, a frame that differs, a broken file
"$bin" vectors digest "$tmp/v" > "$tmp/dg" && grep -qE '^tri 0 [0-9a-f]{8}$' "$tmp/dg" && ok || bad "vectors digest: $(cat "$tmp/dg")"
expect 0 "1 passed, 0 failed" "$bin" vectors check --digests "$tmp/dg" "$tmp/v"
sed 's/ [0-9a-f]*$/ 0badf00d/' "$tmp/dg" > "$tmp/dg-bad"
expect 1 "FAIL tri: frame 0 differs: digest [0-9a-f]{8}, expected 0badf00d" "$bin" vectors check --digests "$tmp/dg-bad" "$tmp/v"
printf 'tri zero\n' > "$tmp/dg-bad"
expect 2 "dg-bad:1: expected NAME FRAME DIGEST" "$bin" vectors check --digests "$tmp/dg-bad" "$tmp/v"
: > "$tmp/dg-bad"
expect 1 "has no digest for frame 0" "$bin" vectors check --digests "$tmp/dg-bad" "$tmp/v"
expect 2 "--digests is for check only" "$bin" vectors bless --digests "$tmp/dg" "$tmp/v"

# render, vp replay, reference, compare
printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5\n v 1 -1 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/t.scene"
expect 0 'frame 0: 1 faces' "$bin" render "$tmp/t.scene" --profile a256 -o "$tmp/t.exr" --png "$tmp/t.png" --stream "$tmp/t.stream"
exrheader "$tmp/t.exr" > "$tmp/t.hdr" 2>&1 && grep -q 'face.id, 32-bit unsigned integer' "$tmp/t.hdr" \
    && grep -q 'compression (type compression): zip' "$tmp/t.hdr" && ok || bad "exrheader: $(cat "$tmp/t.hdr")"
expect 0 'frame 0: 1 faces' "$bin" vp "$tmp/t.stream" --profile a256 -o "$tmp/v.exr"
"$bin" render "$tmp/t.scene" -q -o "$tmp/b512.exr" && ok || bad "render a512"
expect 0 'with a different face \(0.0000%\)' "$bin" compare "$tmp/t.exr" "$tmp/v.exr"
# the same file but for where it came from (albatros.source: the scene, the stream)
[[ $(exrheader "$tmp/t.exr" | grep -v '^file \|albatros.source') == \
   $(exrheader "$tmp/v.exr" | grep -v '^file \|albatros.source') ]] &&
    exrheader "$tmp/v.exr" | grep -q 'albatros.source (type string): "t.stream"' && ok ||
    bad "vp replay's EXR differs from render's: $(diff <(exrheader "$tmp/t.exr") <(exrheader "$tmp/v.exr"))"
expect 1 "t.stream: offset 0: error: word 0: the stream's formats .* differ from the profile's" "$bin" vp "$tmp/t.stream" --profile a512 --json
expect 0 'reference frame 0' "$bin" reference "$tmp/t.scene" --profile a256 -o "$tmp/r.exr"
expect 0 '0 with a different colour; colour error max 0, mean 0.0000, PSNR inf dB' "$bin" compare "$tmp/t.exr" "$tmp/r.exr"
"$bin" render --profile a256 -q -o "$tmp/bv.exr" && "$bin" reference --profile a256 -q -o "$tmp/br.exr" && ok || bad "builtin render/reference"
expect 1 'pixels: [0-9]+ with a different face' "$bin" compare "$tmp/bv.0000.exr" "$tmp/br.0000.exr" --diff "$tmp/d.png"
[[ -s $tmp/d.png ]] && ok || bad "no diff png"
# the names render gave: every numbered frame of both runs, diff images numbered alike
expect 1 '^frame 3: [0-9]+ pixels: [0-9]+ with a different face' "$bin" compare "$tmp/bv.exr" "$tmp/br.exr" --diff "$tmp/ds.png"
[[ -s $tmp/ds.0000.png && -s $tmp/ds.0003.png ]] && ok || bad "numbered diff images"
expect 0 '"frames": \[\{"pixels": 65536, "face_diff": 0' "$bin" compare "$tmp/bv.exr" "$tmp/bv.exr" --json
cp "$tmp/bv.0000.exr" "$tmp/one.0000.exr"
expect 2 'has 4 numbered frames, .* has 1' "$bin" compare "$tmp/bv.exr" "$tmp/one.exr"
expect 2 'is 256x256 .*is 512x512' "$bin" compare "$tmp/t.exr" "$tmp/b512.exr"
expect 2 'cannot' "$bin" compare "$tmp/t.exr" "$tmp/none.exr"
expect 2 "nothing to write" "$bin" render
expect 2 "views are colour" "$bin" render --view bogus:x.png
expect 0 '^judged [0-9]+ of 65536 pixels .*: 0 errors$' "$bin" accuracy "$tmp/t.scene" --profile a256
"$bin" scene random --faces 5 --seed 3 -o "$tmp/r.scene" && "$bin" scene random --faces 5 --seed 3 | cmp -s - "$tmp/r.scene" && ok || bad "scene random not deterministic"
expect 0 '^judged [0-9]+ of 196608 pixels .*: 0 errors$' "$bin" accuracy --random 3 --profile a256
# accuracy judges what it cannot excuse: two quads nearer than near tie in
# the saturated depth store (the first drawn wins, the reference takes the
# nearer); differences there are errors unless excused, and an excused run
# that judges too little of the picture fails too
printf 'albatros-scene 1\nnear 1\nobserver fov 90\nobject a\n v -1 -1 0.5\n v 1 -1 0.5\n v 1 1 0.5\n v -1 1 0.5\n f 1 2 3 4 colour 200 0 0\nend\nobject b\n v -2 -2 0.2\n v 2 -2 0.2\n v 2 2 0.2\n v -2 2 0.2\n f 1 2 3 4 colour 0 200 0\nend\n' > "$tmp/clamp.scene"
expect 1 '^  near-clamp +65536 pixels .* 65536 differ +judged .*the first at pixel \(0, 0\) of frame 0 of' "$bin" accuracy "$tmp/clamp.scene" --profile a256
expect 1 'only 0\.00% of the pixels could be judged' "$bin" accuracy "$tmp/clamp.scene" --profile a256 --exclude near-clamp
expect 0 'warning: 65536 differing pixels nearer than near .* were excluded' "$bin" accuracy "$tmp/clamp.scene" --profile a256 --exclude near-clamp,underflow --min-judged 0
expect 0 '"near-clamp": \{"pixels": 65536, "differ": 65536, "judged": false\}' "$bin" accuracy "$tmp/clamp.scene" --profile a256 --exclude near-clamp --min-judged 0 --json
expect 2 "--exclude edge-band: 'edge-band' is not near-clamp or underflow" "$bin" accuracy "$tmp/clamp.scene" --exclude edge-band
expect 2 "--min-judged 101: expected a percentage" "$bin" accuracy "$tmp/clamp.scene" --min-judged 101

# fidelities: the replay of a stream gives the full run's cycles; counters
"$bin" render "$tmp/t.scene" --profile a256 --fidelity timed --json -q --stream "$tmp/ts.stream" > "$tmp/full.json"
"$bin" vp "$tmp/ts.stream" --profile a256 --fidelity cycle --json -q > "$tmp/replay.json"
grep -o '"timing": {[^}]*}' "$tmp/full.json" > "$tmp/full.t"
grep -o '"timing": {[^}]*}' "$tmp/replay.json" > "$tmp/replay.t"
[[ -s $tmp/full.t ]] && cmp -s "$tmp/full.t" "$tmp/replay.t" && ok || bad "replay cycles differ: $(cat "$tmp/full.t" "$tmp/replay.t")"
expect 0 'cycles = .* fps, within the 50 Hz budget' "$bin" render "$tmp/t.scene" --profile a256 --fidelity timed -o "$tmp/c.exr" --view cycles:"$tmp/cy.png"
[[ -s $tmp/cy.png ]] && ok || bad "no cycles heat map"
exrheader "$tmp/c.exr" | grep -q 'vp.cycles, 32-bit unsigned' && ok || bad "no vp.cycles channel"
expect 1 'has no cycle counts' "$bin" render "$tmp/t.scene" --profile a256 -q --view cycles:"$tmp/x.png"
expect 2 'add --fidelity cycle' "$bin" render "$tmp/t.scene" --profile a256 --vcd "$tmp/x.vcd"
expect 2 'expected FROM:TO' "$bin" render --fidelity cycle --vcd "$tmp/x.vcd" --vcd-window 5
"$bin" render "$tmp/t.scene" --profile a256 --fidelity cycle -q --json --vcd "$tmp/w.vcd" --vcd-window 100:200 > /dev/null && ok || bad "vcd run"
# a256 runs at 20 MHz: 50000 ps a cycle; the window is cycles 100-200
stamps=$(grep '^#' "$tmp/w.vcd" | tr -d '#' | awk '$1 > 0 && ($1 < 5000000 || $1 > 10050000)' | wc -l)
grep -q '^\$enddefinitions' "$tmp/w.vcd" && grep -q '^#5000000$' "$tmp/w.vcd" && [[ $stamps -le 1 ]] && ok || bad "vcd window: $stamps stamps outside"
expect 2 "expected functional, timed or cycle" "$bin" render --fidelity fast
# Ctrl-C during a long traced run: exit 130 and a complete trace
"$bin" scene random --faces 20000 --seed 2 -o "$tmp/heavy.scene"   # ~25 s at cycle fidelity
# interrupted once the trace has begun (its first 64 KiB written), however
# slowly the run starts (under valgrind, parsing alone takes many seconds)
"$bin" render "$tmp/heavy.scene" --profile a1024 --set aa=1 --fidelity cycle --vcd "$tmp/int.vcd" -q > "$tmp/int.out" 2>&1 &
pid=$!
# (the trace is written beside its name, .int.vcd.XXXXXX.tmp, and renamed
# into place when complete: docs/files.md)
for ((i = 0; i < 3000; i++)); do
    for t in "$tmp"/.int.vcd.*.tmp; do [[ -s $t ]] && break 2; done
    sleep 0.1
done
kill -INT $pid
wait $pid
rc=$?
[[ $rc -eq 130 ]] && grep -q 'interrupted at cycle' "$tmp/int.out" && ok || bad "SIGINT: exit $rc: $(cat "$tmp/int.out")"
grep -q '^\$enddefinitions' "$tmp/int.vcd" && tail -n 1 "$tmp/int.vcd" | grep -q '^#[0-9]*$' && ok || bad "interrupted trace incomplete"

# the bridge through the simulated board
expect 0 "1 of 1 frames match the emulator" "$bin" stream --sim --profile a256 "$tmp/t.scene"
expect 0 "hardware agrees with the emulator" "$bin" stream --sim --profile a256 "$tmp/t.scene"
expect 0 '"result": "match"' "$bin" stream --sim --profile a256 --stream "$tmp/ts.stream" --json
expect 0 "restarting the stream" "$bin" stream --sim --profile a256 "$tmp/t.scene" --fault corrupt=60
expect 0 "hardware agrees" "$bin" stream --sim --profile a256 --fault swap=3
expect 0 "resuming from frame 2" "$bin" stream --sim --profile a256 --fault drop=6
expect 1 "frame 0: the board's frame CRC .* first at pixel \(5, 7\) channel G" "$bin" stream --sim --profile a256 "$tmp/t.scene" --fault flip=0
expect 3 "the board stopped answering" "$bin" stream --sim --profile a256 "$tmp/t.scene" --fault silence=1 --timeout 50
expect 3 "device disconnected" "$bin" stream --sim --profile a256 "$tmp/t.scene" --fault disconnect=100 --wait 0
# hot-plug: the board comes back (a new simulated board) and the stream starts over
expect 0 "disconnected 1 time and came back" "$bin" stream --sim --profile a256 "$tmp/t.scene" --fault disconnect=100
expect 0 '"reattaches": 1' "$bin" stream --sim --profile a256 --fault disconnect=3000 --json
# frames mode: the rendered frames as tiles; the simulated display ends on the last
expect 0 "the simulated display shows frame 3: identical" "$bin" stream --sim --frames --profile a256
expect 0 "1 resends" "$bin" stream --sim --frames --profile a256 --fault drop=3
expect 0 '"display": "identical"' "$bin" stream --sim --frames --profile a256 --fault corrupt=5000 --json
expect 3 "stopped answering" "$bin" stream --sim --frames --profile a256 --fault silence=1 --timeout 20
expect 0 "albatros-sim: protocol 1, .* VP 256x256 8-bit colour" "$bin" board info --sim --profile a256
expect 0 "board reset" "$bin" board reset --sim
expect 0 "sim:0" "$bin" board list --sim
expect 2 "expected corrupt" "$bin" stream --sim --fault bogus=1

# the stability sweep: one family job, the report (CSV, Markdown, gnuplot PNG)
expect 0 "albatros stability .* --family sliver" "$bin" stability --jobs --out "$tmp/st"
expect 0 "" "$bin" stability --family cyclic --seeds 1 --out "$tmp/st"
[[ $(head -1 "$tmp/st/stability-cyclic.csv") == family,step,severity,config,face_diff_pct,psnr_db,ms_per_frame,failed ]] \
    && [[ $(wc -l < "$tmp/st/stability-cyclic.csv") -eq 69 ]] && ok || bad "stability CSV: $(head -3 "$tmp/st/stability-cyclic.csv")"
expect 0 "wrote .*stability.png" "$bin" stability --report --out "$tmp/st"
grep -q '^### cyclic' "$tmp/st/stability.md" && grep -q '| painter | severity' "$tmp/st/stability.md" && ok || bad "stability.md"
[[ $(head -c 8 "$tmp/st/stability.png" | od -An -tx1 | tr -d ' ') == 89504e470d0a1a0a ]] && ok || bad "stability.png is not a PNG"
expect 2 "unknown \(known:" "$bin" stability --family nope
expect 1 "no stability-FAMILY.csv" "$bin" stability --report --out "$tmp/empty"

# same input, same output: the environment, the locale, the working directory
# and the thread count change no byte of any file written
abin=$(realpath "$bin")
det() {   # det DIR THREADS: every output of render, gp and the cycle model into DIR
    mkdir -p "$1" && cd "$1" || return 1
    "$abin" render --threads "$2" -q -o f.exr --png f.png --view level:l.png --stream f.stream \
        --json > f.json &&
    "$abin" gp -q --hex f.hex -o g.stream &&
    "$abin" render --profile t32 --fidelity cycle --vcd c.vcd -q -o c.exr --view cycles:c.png
    local rc=$?
    cd - > /dev/null
    return $rc
}
# a decimal-comma locale where one is installed (CI generates de_DE.UTF-8):
# a printf of a double after a setlocale() would show it
loc=$(locale -a 2>/dev/null | grep -im1 '^de_DE\.utf-\?8$')
[[ -n $loc ]] || echo "note: no de_DE locale installed; the determinism run uses C.utf8" >&2
(env -i PATH="$PATH" HOME=/nonexistent bash -c "$(declare -f det); abin='$abin'; det '$tmp/det1' 1") &&
    (LC_ALL=${loc:-C.utf8} TZ=Asia/Novosibirsk OMP_NUM_THREADS=7 \
     MALLOC_PERTURB_=165 det "$tmp/det2" 3) && ok || bad "determinism runs failed"
ndet=0
for f in "$tmp"/det1/*; do
    cmp -s "$f" "$tmp/det2/${f##*/}" && ndet=$((ndet + 1)) || bad "determinism: ${f##*/} differs"
done
[[ $ndet -ge 14 ]] && ok || bad "determinism: only $ndet files compared"

finish
