#!/usr/bin/env bash
# cli-timing.sh ALBATROS — the timed and cycle models from the command line:
# option misuse, the summary, the JSON fields against their documentation,
# and the VCD trace's pixel writes against the frames' counters.  Small
# scenes on t32: this also runs under valgrind.
source "$(dirname "$0")/lib.sh"
docs="$(dirname "$0")/../docs"

printf 'albatros-scene 1\nobserver fov 90\nobject t\n v -1 -1 5\n v 1 -1 5\n v 0 1 5\n f 1 2 3\nend\n' > "$tmp/t.scene"
# two frames: a near triangle, then a far one it partly hides (samples
# covered but not written)
printf 'albatros-scene 1\nobserver fov 90\nobject u\n v -1 1 2\n v 0 -1 2\n v 1 1 2\n f 1 2 3\nend\nobject t\n v -1 -1 3\n v 1 -1 3\n v 0 1 3\n f 1 2 3\nend\nframe\nframe\n' > "$tmp/two.scene"

# help: every view, including the heat map of cycles
expect 0 'level, coverage,' "$bin" render --help
expect 0 '^ +cycles \(timed or cycle fidelity\)' "$bin" render --help

# --vcd-window limits a trace: without --vcd it is an error, not ignored
expect 2 '--vcd-window limits a trace: add --vcd FILE' "$bin" render "$tmp/t.scene" --profile t32 --json --vcd-window 1:2
expect 2 '--vcd-window limits a trace' "$bin" render --vcd-window 1:2
expect 2 '--vcd-window limits a trace' "$bin" render "$tmp/t.scene" --profile t32 --fidelity cycle -o "$tmp/w.exr" --vcd-window 0:10
"$bin" gp "$tmp/t.scene" --profile t32 -q -o "$tmp/t.stream" && ok || bad "gp t32"
expect 2 'albatros vp: --vcd-window limits a trace' "$bin" vp "$tmp/t.stream" --profile t32 --json --vcd-window 1:2
[[ ! -e $tmp/w.exr ]] && ok || bad "a refused run wrote its frame"
# a window of one cycle, cycle 0, is a window (t32: 100000 ps a cycle): the
# header, cycle 0's two edges and the final timestamp
"$bin" render "$tmp/t.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/w0.vcd" --vcd-window 0:0 \
    && ok || bad "vcd window 0:0"
late=$(grep '^#' "$tmp/w0.vcd" | tr -d '#' | awk '$1 > 50000' | wc -l)
[[ $late -eq 1 ]] && ok || bad "vcd window 0:0: $late timestamps after cycle 0"

# the summary: cells per level, which sum to the cells visited
out=$("$bin" render "$tmp/two.scene" --profile t32 --fidelity timed -o "$tmp/s.exr" 2>&1)
line=$(grep -E '^frame 1: ' <<<"$out")
if [[ $line =~ ([0-9]+)\ cells\ visited\ \(by\ level:\ ([0-9 ]+)\) ]]; then
    total=${BASH_REMATCH[1]} levels=(${BASH_REMATCH[2]}) sum=0
    for n in "${levels[@]}"; do sum=$((sum + n)); done
    # t32: 32 x 32 samples, levels 0 to 5
    [[ ${#levels[@]} -eq 6 && $sum -eq $total && ${levels[0]} -eq 2 ]] && ok ||
        bad "cells per level ${levels[*]} (sum $sum) vs $total visited"
else
    bad "summary lacks cells per level: $out"
fi

# every JSON field of render (and vp, reference) is documented by name
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle --json -q > "$tmp/r.json" && ok || bad "render --json"
"$bin" reference "$tmp/t.scene" --profile t32 --json -q > "$tmp/ref.json" && ok || bad "reference --json"
keys=$(grep -ohE '"[a-z_0-9]+":' "$tmp/r.json" "$tmp/ref.json" | sort -u | tr -d '":')
nkeys=0
for k in $keys; do
    nkeys=$((nkeys + 1))
    grep -q "\`$k\`" "$docs/microarchitecture.md" || bad "JSON field $k is not in docs/microarchitecture.md"
done
[[ $nkeys -ge 30 ]] && ok || bad "only $nkeys JSON fields seen"

# the trace's pixel writes: pipe.written summed over the run equals the
# frames' samples_written, and pipe.samples their samples_covered
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle -q --json --vcd "$tmp/p.vcd" > "$tmp/p.json" \
    && ok || bad "traced run"
want_w=$(grep -oE '"samples_written": [0-9]+' "$tmp/p.json" | awk '{ s += $2 } END { print s }')
want_c=$(grep -oE '"samples_covered": [0-9]+' "$tmp/p.json" | awk '{ s += $2 } END { print s }')
# sum NAME: a pipe signal's value times the cycles it held (100000 ps each)
sum() {
    awk -v name="$1" '
        $1 == "$scope" { scope = $3 }
        $1 == "$var" && scope == "pipe" && $5 == name { id = $4 }
        /^#/ { now = substr($1, 2) + 0; next }
        id != "" && /^b/ && $2 == id {
            s += v * int((now - since) / 100000); since = now
            v = 0; n = length($1); for (i = 2; i <= n; i++) v = v * 2 + substr($1, i, 1)
        }
        END { s += v * int((now - since) / 100000); print s + 0 }' "$tmp/p.vcd"
}
got_w=$(sum written) got_c=$(sum samples)
[[ $want_w -gt 0 && $got_w -eq $want_w ]] && ok || bad "trace writes $got_w samples, frames $want_w"
[[ $want_c -gt $want_w && $got_c -eq $want_c ]] && ok || bad "trace passes $got_c samples, frames $want_c"
grep -qE '^\$var wire 1 [^ ]+ write \$end' "$tmp/p.vcd" && ok || bad "no write strobe declared"

finish
