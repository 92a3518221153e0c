#!/usr/bin/env bash
# cli-scale.sh ALBATROS — work and memory grow as the input does, no faster:
# parsing is linear in the statements (instructions counted by valgrind's
# cachegrind, not wall time), memory does not grow with the frames of gp and
# of the functional render, and a timed run that cannot fit is refused
# before the memory runs out (docs/limits.md).
source "$(dirname "$0")/lib.sh"
bin=$(realpath "$bin")

# instructions FILE: the instructions albatros gp FILE --json executes (the
# program itself, not make memcheck's valgrind wrapper)
instructions() {
    valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
        "${ALBATROS_UNWRAPPED:-$bin}" gp "$@" --json 2>&1 >/dev/null | sed -n 's/.*I *refs: *//p' | tr -d ,
}
if ! command -v valgrind > /dev/null; then
    bad "valgrind is needed to count instructions (apt-get install valgrind; make deps)"
elif nm "${ALBATROS_UNWRAPPED:-$bin}" 2>/dev/null | grep -q __asan_init; then
    echo "# instruction counts: not under AddressSanitizer (valgrind cannot run it)"
else
    # N unknown keywords and N undefined materials, each a new name
    objs() {
        { printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n'
          for ((i = 0; i < $1; i++)); do printf 'kw%d 1\nusemtl m%d\n' $i $i; done; } > "$2"
    }
    objs 0 "$tmp/k0.obj"; objs 2000 "$tmp/k1.obj"; objs 20000 "$tmp/k10.obj"
    i0=$(instructions "$tmp/k0.obj") i1=$(instructions "$tmp/k1.obj") i10=$(instructions "$tmp/k10.obj")
    # linear: ten times the statements, about ten times the instructions (a
    # linear search per name made it a hundred)
    ratio=$(awk -v a="$i0" -v b="$i1" -v c="$i10" 'BEGIN { printf "%.1f", (c - a) / (b - a) }')
    awk -v r="$ratio" 'BEGIN { exit !(r > 5 && r < 14) }' && ok ||
        bad "OBJ parsing: 20000 names cost $ratio times 2000 (instructions $i0, $i1, $i10)"
    echo "# OBJ names: $i0 / $i1 / $i10 instructions for 0 / 2000 / 20000: x$ratio"
    # each name warned once, the first ten of a kind by name, the rest counted
    out=$("$bin" gp "$tmp/k10.obj" --json 2>&1 >/dev/null)
    [[ $(grep -c "statements are not supported" <<<"$out") -eq 10 &&
       $(grep -c "is not defined in any material library" <<<"$out") -eq 10 ]] &&
        grep -q "19990 more statements of 19990 other unsupported keywords were ignored, the first on line 25" <<<"$out" &&
        grep -q "19990 more materials are not defined in any material library, the first on line 26" <<<"$out" &&
        ok || bad "OBJ warnings: $(wc -l <<<"$out") lines: $(tail -3 <<<"$out")"
    # the scene format: N objects, or one object over N frames that each move it
    objects() {
        { echo 'albatros-scene 1'
          for ((i = 0; i < $1; i++)); do printf 'object o%d at 0 0 50\n v 0 0 0\n v 1 0 0\n v 0 1 0\n f 1 2 3\nend\n' $i; done; } > "$2"
    }
    frames() {
        { echo 'albatros-scene 1'; printf 'object o at 0 0 50\n v 0 0 0\n v 1 0 0\n v 0 1 0\n f 1 2 3\nend\n'
          for ((i = 0; i < $1; i++)); do printf 'frame\n pose o yaw %d\n' $((i % 7)); done; } > "$2"
    }
    for kind in objects frames; do
        $kind 1 "$tmp/s0.scene"; $kind 1000 "$tmp/s1.scene"; $kind 10000 "$tmp/s10.scene"
        i0=$(instructions "$tmp/s0.scene") i1=$(instructions "$tmp/s1.scene") i10=$(instructions "$tmp/s10.scene")
        ratio=$(awk -v a="$i0" -v b="$i1" -v c="$i10" 'BEGIN { printf "%.1f", (c - a) / (b - a) }')
        awk -v r="$ratio" 'BEGIN { exit !(r > 5 && r < 14) }' && ok ||
            bad "scene $kind: 10000 cost $ratio times 1000 (instructions $i0, $i1, $i10)"
        echo "# scene $kind: $i0 / $i1 / $i10 instructions for 1 / 1000 / 10000: x$ratio"
    done
fi

# memory: gp and the functional render hold one frame's stream, not all
# frames' (measured as the peak resident size of the process)
"$bin" scene random --faces 2000 --seed 4 --size 0.02 -o "$tmp/f1.scene"
{ cat "$tmp/f1.scene"; for ((i = 0; i < 100; i++)); do echo frame; done; } > "$tmp/f100.scene"
peak() {   # peak KB of albatros ARGS
    python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)' "$bin" "$@"
}
for cmd in "gp --json -o $tmp/x.stream --memh $tmp/x.memh" "render --profile a256 --json --threads 1 --stream $tmp/x.stream"; do
    # shellcheck disable=SC2086
    m1=$(peak ${cmd%% *} "$tmp/f1.scene" ${cmd#* }) m100=$(peak ${cmd%% *} "$tmp/f100.scene" ${cmd#* })
    awk -v a="$m1" -v b="$m100" 'BEGIN { exit !(b < 1.3 * a) }' && ok ||
        bad "${cmd%% *}: 100 frames peak at $m100 KB, 1 frame at $m1 KB"
    echo "# ${cmd%% *}: peak $m1 KB for 1 frame, $m100 KB for 100"
done
# the stream written frame by frame is the stream made at once
"$bin" gp "$tmp/f100.scene" --profile a256 -q -o "$tmp/a.stream"
"$bin" render "$tmp/f100.scene" --profile a256 -q --json --stream "$tmp/b.stream" > /dev/null 2>&1
cmp -s "$tmp/a.stream" "$tmp/x.stream" && cmp -s "$tmp/a.stream" "$tmp/b.stream" && ok || bad "streams differ"
# a timed run whose stream cannot fit is refused at its first frames, not
# at the end of the memory: 500,000 frames of about 90 KB (some 140 GB with
# the model's copy), more than a test machine has
{ cat "$tmp/f1.scene"; for ((i = 0; i < 500000; i++)); do echo frame; done; } > "$tmp/huge.scene"
SECONDS=0
expect 1 "the word stream of these 500000 frames needs about [0-9]+ MB in memory .* with --fidelity timed, more than the [0-9]+ MB available; .*--fidelity functional" \
    "$bin" render "$tmp/huge.scene" --fidelity timed --json
[[ $SECONDS -lt 60 ]] && ok || bad "the refusal took $SECONDS s"
# and under a limit (ulimit -v) the budget is the limit (not under ASan,
# whose shadow memory needs more address space than any limit leaves)
if ! nm "${ALBATROS_UNWRAPPED:-$bin}" 2>/dev/null | grep -q __asan_init && [[ -z ${ALBATROS_UNWRAPPED:-} ]]; then
    { cat "$tmp/f1.scene"; for ((i = 0; i < 20000; i++)); do echo frame; done; } > "$tmp/big.scene"
    expect 1 "the word stream of these 20000 frames needs about [0-9]+ MB in memory .*, more than the 1049 MB available" \
        bash -c "ulimit -v 1024000; $bin render $tmp/big.scene --fidelity timed --json"
fi

# numbers that cannot be right are refused, not wrapped
expect 2 "--faces 0: expected 1 to 10000000" "$bin" scene random --faces 0
expect 2 "--per-angle 0: expected 1 to 10000000" "$bin" scene slivers --per-angle 0
expect 2 "--vcd-window 1:99999999999999999999999: expected FROM:TO cycles, decimal, FROM <= TO <= 18446744073709551615" \
    "$bin" render --fidelity cycle --vcd "$tmp/w.vcd" --vcd-window 1:99999999999999999999999
expect 2 "--vcd-window 18446744073709551616:1" "$bin" render --fidelity cycle --vcd "$tmp/w.vcd" --vcd-window 18446744073709551616:1
expect 0 "" "$bin" render "$tmp/f1.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/w.vcd" --vcd-window 0:18446744073709551615

finish
