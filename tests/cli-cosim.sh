#!/usr/bin/env bash
# cli-cosim.sh ALBATROS — what an RTL bench reads and writes from the command
# line: the cycle model's event log (--events) against the frames' own
# statistics, the $readmemh stream (gp --memh) read back and loaded by an
# Icarus Verilog bench, and the library's exported names (nm).
source "$(dirname "$0")/lib.sh"
build=$(dirname "$bin")
[[ -x $build/albatros ]] || build=build   # under memcheck $bin is a wrapper

printf 'albatros-scene 1\nobserver fov 90\nobject u\n v -1 1 2\n v 0 -1 2\n v 1 1 2\n f 1 2 3\nend\nobject t\n v -1 -1 3\n v 1 -1 3\n v 0 1 3\n f 1 2 3\nend\nframe\nframe\n' > "$tmp/two.scene"

# ---- the event log ----
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle -q --events "$tmp/ev.txt" --json > "$tmp/r.json" \
    && ok || bad "render --events"
"$bin" gp "$tmp/two.scene" --profile t32 -q -o "$tmp/two.stream" && ok || bad "gp"
words=$(( $(stat -c %s "$tmp/two.stream") / 4 ))
kinds() { awk -v k="$1" '$2 == k' "$tmp/ev.txt" | wc -l; }
[[ $(kinds push) -eq $words && $(kinds pop) -eq $words ]] && ok ||
    bad "pushes $(kinds push), pops $(kinds pop), $words words"
written=$(grep -o '"samples_written": [0-9]*' "$tmp/r.json" | awk '{s += $2} END {print s}')
[[ $(kinds write) -eq $written && $written -gt 0 ]] && ok || bad "writes $(kinds write) vs samples_written $written"
faces=$(grep -o '"faces": [0-9]*' "$tmp/r.json" | awk '{s += $2} END {print s}')
[[ $(kinds start) -eq $faces && $(kinds end) -eq $faces && $(kinds load) -eq $faces ]] && ok ||
    bad "faces: load $(kinds load) start $(kinds start) end $(kinds end), $faces drawn"
# each frame line carries the retirement cycle and cycle count of the JSON
retire=$(grep -o '"retire": [0-9]*' "$tmp/r.json" | awk '{print $2}' | tr '\n' ' ')
ev_retire=$(awk '$2 == "frame" {print $1}' "$tmp/ev.txt" | tr '\n' ' ')
[[ -n $retire && $retire == "$ev_retire" ]] && ok || bad "frame cycles '$ev_retire' vs retire '$retire'"
# cycles never go back, and a pop comes after its push
awk 'NR > 1 && $1 < last {bad = 1} {last = $1}
     $2 == "push" {p[$3] = $1} $2 == "pop" && !($3 in p && $1 > p[$3]) {bad = 1}
     END {exit bad}' "$tmp/ev.txt" && ok || bad "event order"
# the CRCs are the simulated board's (a separate run through the bridge)
"$bin" stream --sim "$tmp/two.scene" --profile t32 --json > "$tmp/s.json" 2>/dev/null && ok || bad "stream --sim"
crc_board=$(grep -o '"crc": "[0-9a-f]*"' "$tmp/s.json" | grep -o '[0-9a-f]\{8\}' | tr '\n' ' ')
crc_ev=$(awk '$2 == "frame" {print substr($5, 3)}' "$tmp/ev.txt" | tr '\n' ' ')
[[ -n $crc_ev && $crc_ev == "$crc_board" ]] && ok || bad "frame CRCs '$crc_ev' vs the board's '$crc_board'"
# the VP alone on the stream logs the same events; --events-only keeps kinds
"$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle -q --events "$tmp/ev2.txt" && ok || bad "vp --events"
cmp -s "$tmp/ev.txt" "$tmp/ev2.txt" && ok || bad "vp and render logs differ"
"$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle -q --events - --events-only frame,pop > "$tmp/ev3.txt" \
    && ok || bad "--events - --events-only"
grep -E ' (pop|frame) ' "$tmp/ev.txt" | cmp -s - "$tmp/ev3.txt" && ok || bad "--events-only frame,pop"
expect 2 'add --fidelity cycle' "$bin" vp "$tmp/two.stream" --profile t32 --events "$tmp/x.txt"
expect 2 'unknown kind .pixel.; kinds are all, push, pop' "$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle --events "$tmp/x.txt" --events-only pop,pixel
expect 2 '--events-only limits the event log' "$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle --json --events-only pop
expect 1 'No such file or directory' "$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle --events "$tmp/no/dir/x.txt"

# ---- the stream as $readmemh text ----
"$bin" gp "$tmp/two.scene" --profile t32 -q --memh "$tmp/two.memh" && ok || bad "gp --memh"
[[ $(grep -cv '^//' "$tmp/two.memh") -eq $words ]] && ok || bad "memh lines"
"$bin" dump "$tmp/two.stream" > "$tmp/d1.txt" && "$bin" dump "$tmp/two.memh" > "$tmp/d2.txt" && ok || bad "dump memh"
cmp -s "$tmp/d1.txt" "$tmp/d2.txt" && ok || bad "dump of memh and binary differ"
"$bin" vp "$tmp/two.memh" --profile t32 --fidelity cycle -q --events "$tmp/ev4.txt" && cmp -s "$tmp/ev.txt" "$tmp/ev4.txt" \
    && ok || bad "vp on memh"
# what $readmemh accepts and a stream cannot, named by line and column
printf 'a5010002\n@7 0000180a\n' > "$tmp/hole.memh"
expect 1 'hole.memh:2:1: error: address @7: the file has no holes' "$bin" dump "$tmp/hole.memh"
printf '// x\na5010002 1xz0\n' > "$tmp/xz.memh"
expect 1 'xz.memh:2:10: error: expected a hex value .* found .1xz0.' "$bin" dump "$tmp/xz.memh"
printf 'a5010002 123456789\n' > "$tmp/wide.memh"
expect 1 'wide.memh:1:10: error: value wider than 32 bits' "$bin" dump "$tmp/wide.memh"
printf '/* open\na5010002\n' > "$tmp/open.memh"
expect 1 'open.memh:1:1: error: unterminated comment' "$bin" dump "$tmp/open.memh"
# comments, underscores and the next address are $readmemh's and accepted
{ echo '/* the stream */ @0'; sed -n '2,$p' "$tmp/two.memh" | sed '1s/^\(....\)/\1_/'; } > "$tmp/ok.memh"
"$bin" dump "$tmp/ok.memh" > "$tmp/d3.txt" && cmp -s "$tmp/d1.txt" "$tmp/d3.txt" && ok || bad "memh with comments"

# an Icarus Verilog bench loads it: word count and a checksum computed here
# from the binary stream
if command -v iverilog >/dev/null; then
    sum=$(od -An -v -tu4 -w4 "$tmp/two.stream" | awk '{s = (s * 31 + $1) % 4294967296; n++}
                                                     END {printf "%d %08x\n", n, s}')
    cat > "$tmp/tb.sv" <<'EOF'
module tb;
  logic [31:0] mem [0:65535];
  int n = 0;
  logic [31:0] sum = 0;
  initial begin
    for (int i = 0; i < 65536; i++) mem[i] = 'x;
    $readmemh(`MEMH, mem);
    for (int i = 0; i < 65536 && !$isunknown(mem[i]); i++) begin
      sum = sum * 31 + mem[i];
      n++;
    end
    $display("%0d %08x", n, sum);
  end
endmodule
EOF
    if iverilog -g2012 -DMEMH="\"$tmp/two.memh\"" -o "$tmp/tb.vvp" "$tmp/tb.sv" 2>"$tmp/iv.log"; then
        got=$(vvp -n "$tmp/tb.vvp" 2>/dev/null | grep -E '^[0-9]+ [0-9a-f]{8}$')
        [[ $got == "$sum" ]] && ok || bad "Icarus read '$got', expected '$sum'"
    else
        bad "iverilog: $(cat "$tmp/iv.log")"
    fi
else
    bad "iverilog is not installed (apt-get install iverilog)"
fi

# ---- frame-store dumps: the model's, and one rewritten by an Icarus bench ----
"$bin" render "$tmp/two.scene" --profile t32 -q -o "$tmp/f.exr" --dump "$tmp/f.memh" && ok || bad "render --dump"
expect 0 '1024 pixels: 0 with a different face' "$bin" compare "$tmp/f.0001.memh" "$tmp/f.0001.exr"
expect 0 'frame 1: 1024 pixels: 0 with' "$bin" compare "$tmp/f.memh" "$tmp/f.exr"
"$bin" render "$tmp/two.scene" --profile t32 -q --dump "$tmp/g.raw" && ok || bad "render --dump raw"
[[ $(stat -c %s "$tmp/g.0000.raw") -eq $((32 * 32 * 16)) ]] && ok || bad "raw dump size"
expect 0 '0 with a different face' "$bin" compare "$tmp/g.0000.raw" "$tmp/f.0000.exr"
expect 0 '0 with a different face' "$bin" compare "$tmp/g.0000.raw" "$tmp/f.0000.memh" --profile t32
# an SV bench loads the dump with $readmemh, changes pixel (5, 7)'s G by
# one and pixel (30, 9)'s level, and writes it back with $writememh, as an
# RTL bench dumps its frame store
if command -v iverilog >/dev/null; then
    cat > "$tmp/fb.sv" <<'SV'
module fb;
  logic [127:0] mem [0:1023];
  initial begin
    $readmemh(`IN, mem);
    mem[7 * 32 + 5][47:32] = mem[7 * 32 + 5][47:32] + 1;
    mem[9 * 32 + 30][15:8] = 8'd3;
    $writememh(`OUT, mem);
  end
endmodule
SV
    iverilog -g2012 -DIN="\"$tmp/f.0001.memh\"" -DOUT="\"$tmp/rtl.memh\"" -o "$tmp/fb.vvp" "$tmp/fb.sv" \
        && vvp -n "$tmp/fb.vvp" > /dev/null && ok || bad "Icarus dump bench"
    expect 1 '2 pixels differ; the first at pixel \(5, 7\): vp.G [0-9]+ in .*rtl.memh' \
        "$bin" compare "$tmp/rtl.memh" "$tmp/f.0001.exr"
    "$bin" compare "$tmp/rtl.memh" "$tmp/f.0001.exr" --json > "$tmp/c.json"
    python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); f = j["first_diff"]
assert (f["x"], f["y"], f["channel"], f["a"] - f["b"]) == (5, 7, "vp.G", 1), j
assert j["pixels_diff"] == 2, j' "$tmp/c.json" && ok || bad "compare --json: $(cat "$tmp/c.json")"
fi
# EXR against EXR counts what is seen (face, colour, coverage); --exact every plane
"$bin" reference "$tmp/two.scene" --profile t32 -q -o "$tmp/r.exr" && ok || bad "reference"
"$bin" compare "$tmp/f.0000.exr" "$tmp/r.0000.exr" > "$tmp/vis.txt"
"$bin" compare --exact "$tmp/f.0000.exr" "$tmp/r.0000.exr" > "$tmp/ex.txt"; ex=$?
[[ $ex -eq 1 ]] && grep -q 'vp\.\(level\|depth\)' "$tmp/ex.txt" && ok || bad "--exact: $ex $(cat "$tmp/ex.txt")"
grep -q 'vp\.\(level\|depth\)' "$tmp/vis.txt" && bad "without --exact levels count: $(cat "$tmp/vis.txt")" || ok
# a dump is held against the model in every plane
expect 1 "first at pixel .*: vp\.(level|depth)" "$bin" compare "$tmp/g.0000.raw" "$tmp/r.0000.exr"
printf '\001\002\003\004' > "$tmp/short.raw"
expect 2 'short.raw: offset 4: error: a raw dump of 32x32 pixels is 16384 bytes, this one 4' \
    "$bin" compare "$tmp/short.raw" "$tmp/f.0000.exr"

# ---- vectors check --junit: one test case per vector, parsed by a real XML parser ----
mkdir -p "$tmp/v"
cp -r test-vectors/shared-edges "$tmp/v/good" && cp -r test-vectors/shared-edges "$tmp/v/bad&<odd>" \
    && cp -r test-vectors/shared-edges "$tmp/v/known" && ok || bad "copy vectors"
# a changed word in one stream, a changed counter in a known failure
printf '\x01' | dd of="$tmp/v/bad&<odd>/expected.stream" bs=1 seek=44 conv=notrunc status=none
sed -i '1s/engine_busy=/engine_busy=1/' "$tmp/v/known/expected.cycles"
echo "engine counts under review" > "$tmp/v/known/KNOWN-FAILURE"
"$bin" vectors check --junit "$tmp/j.xml" --diff-dir "$tmp/diffs" "$tmp/v" > "$tmp/jv.out" 2>&1
rc=$?
[[ $rc -eq 1 ]] && ok || bad "vectors check with a failure: exit $rc"
python3 - "$tmp/j.xml" <<'PY' && ok || bad "JUnit report: $(cat "$tmp/j.xml")"
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == "testsuites" and root.get("tests") == "3" and root.get("failures") == "1", root.attrib
cases = {c.get("name"): c for c in root.iter("testcase")}
assert set(cases) == {"good", "bad&<odd>", "known"}, cases
assert len(cases["good"]) == 0
f = cases["bad&<odd>"].find("failure")
assert f is not None and "stream differs at word 11" in f.get("message"), f.attrib
assert "expected" in f.text and "got" in f.text, f.text
k = cases["known"].find("skipped")
assert k is not None and "engine counts under review" in k.get("message"), k.attrib
PY
expect 2 '--junit reports a check' "$bin" vectors bless --junit "$tmp/j3.xml" "$tmp/v"
expect 1 'junit /nonexistent/j.xml' "$bin" vectors check --junit /nonexistent/j.xml "$tmp/v" good

# ---- the library exports alb_* and nothing else ----
so=$(ls "$build"/lib/libalbatros.so.*.*.* 2>/dev/null | head -1)
if [[ -n $so ]]; then
    others=$(nm -D --defined-only "$so" | awk '$2 != "A" && $3 !~ /^alb_/')
    [[ -z $others ]] && ok || bad "libalbatros.so exports: $others"
    n=$(nm -D --defined-only "$so" | awk '$3 ~ /^alb_/' | wc -l)
    (( n > 100 )) && ok || bad "only $n alb_ symbols exported"
    readelf -d "$so" | grep -q 'SONAME.*\[libalbatros\.so\.0\]' && ok || bad "SONAME"
    leaks=$(nm -g --defined-only "$build/lib/libalbatros.a" | awk 'NF == 3 && $3 !~ /^alb_/')
    [[ -z $leaks ]] && ok || bad "libalbatros.a has global names: $(head -c 300 <<<"$leaks")"
else
    bad "no shared library in $build/lib"
fi

finish
