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

# --vcd-units: a trace of some units; like --vcd-window it needs --vcd
expect 2 '--vcd-units limits a trace: add --vcd FILE' "$bin" render "$tmp/t.scene" --profile t32 --json --vcd-units fifo
expect 2 'albatros vp: --vcd-units limits a trace' "$bin" vp "$tmp/t.stream" --profile t32 --json --vcd-units fifo
units='all, gp, fifo, parser, engine, fill, pipe'
expect 2 "--vcd-units fifo,fills: unknown unit 'fills'; units are $units\$" \
    "$bin" render "$tmp/t.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/x.vcd" --vcd-units fifo,fills
expect 2 "albatros vp: --vcd-units Fifo: unknown unit 'Fifo'; units are $units\$" \
    "$bin" vp "$tmp/t.stream" --profile t32 --fidelity cycle -q --vcd "$tmp/x.vcd" --vcd-units Fifo
expect 2 "empty unit name; units are $units\$" \
    "$bin" render "$tmp/t.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/x.vcd" --vcd-units fifo,
# the valid names are the scopes of a full trace, in --help and the docs
for u in ${units//,/}; do
    [[ $u == all ]] || grep -qE "^\\\$scope module $u \\\$end" "$tmp/p.vcd" || bad "unit $u is not a scope of the trace"
    "$bin" render --help | sed -n '/--vcd-units/,/--json/p' | grep -qw "$u" || bad "render --help lacks unit $u"
    grep -q "\`$u\`" "$docs/microarchitecture.md" || bad "unit $u is not in docs/microarchitecture.md"
done
ok
expect 0 '--vcd-units' "$bin" vp --help

# changes UNIT FILE: "time scope.signal value" for the top scope's signals
# and UNIT's, identifiers mapped to names
changes() {
    awk -v want="$1" '
        $1 == "$scope" { scope[++depth] = $3; next }
        $1 == "$upscope" { depth--; next }
        $1 == "$var" { if (depth == 1 || scope[depth] == want) name[$4] = (depth > 1 ? want "." : "") $5; next }
        /^\$/ { next }
        /^#/ { now = substr($1, 2); next }
        /^b/ { if ($2 in name) print now, name[$2], substr($1, 2); next }
        { id = substr($1, 2); if (id in name) print now, name[id], substr($1, 1, 1) }' "$2"
}
# the two-frame scene, cycles 20 to 400, in full and of the fifo alone
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/all.vcd" --vcd-window 20:400 \
    && ok || bad "full trace"
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/f.vcd" --vcd-window 20:400 \
    --vcd-units fifo && ok || bad "trace of the fifo"
scopes=$(grep -oE '^\$scope module [a-z]+' "$tmp/f.vcd" | awk '{ print $3 }' | tr '\n' ' ')
[[ $scopes == 'albatros fifo ' ]] && ok || bad "trace of the fifo has scopes: $scopes"
grep -qE '^\$var wire 1 [^ ]+ clk \$end' "$tmp/f.vcd" && grep -q '^\$enddefinitions \$end' "$tmp/f.vcd" \
    && grep -q '^\$dumpvars' "$tmp/f.vcd" && ok || bad "trace of the fifo: header"
[[ $(grep -c '^\$var' "$tmp/f.vcd") -eq 7 ]] && ok || bad "trace of the fifo: not 7 variables"
# no values of the units left out: every change is of a declared identifier
undeclared=$(awk '$1 == "$var" { id[$4] = 1; next } /^[#$]/ { next }
    /^b/ { if (!($2 in id)) n++; next } { if (!(substr($1, 2) in id)) n++ } END { print n + 0 }' "$tmp/f.vcd")
[[ $undeclared -eq 0 ]] && ok || bad "trace of the fifo: $undeclared changes of undeclared signals"
changes fifo "$tmp/all.vcd" > "$tmp/all.ch"
changes fifo "$tmp/f.vcd" > "$tmp/f.ch"
n=$(grep -c ' fifo\.push 1$' "$tmp/f.ch")
[[ $n -gt 5 ]] && ok || bad "trace of the fifo: $n pushes"
cmp -s "$tmp/all.ch" "$tmp/f.ch" && ok || bad "fifo changes differ from the full trace: $(diff "$tmp/all.ch" "$tmp/f.ch" | head -5)"
full=$(wc -c < "$tmp/all.vcd") part=$(wc -c < "$tmp/f.vcd")
[[ $part -lt $full ]] && ok || bad "trace of the fifo ($part bytes) not smaller than the full one ($full)"
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/f2.vcd" --vcd-window 20:400 \
    --vcd-units fifo && cmp -s "$tmp/f.vcd" "$tmp/f2.vcd" && ok || bad "two traces of the fifo differ"
# all is the full trace; vp takes the option too, and a list keeps trace order
"$bin" render "$tmp/two.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/a.vcd" --vcd-window 20:400 \
    --vcd-units pipe,all && cmp -s "$tmp/all.vcd" "$tmp/a.vcd" && ok || bad "--vcd-units pipe,all is not the full trace"
"$bin" gp "$tmp/two.scene" --profile t32 -q -o "$tmp/two.stream" && ok || bad "gp two.scene"
"$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle -q --vcd "$tmp/v.vcd" --vcd-units pipe,engine \
    && ok || bad "vp --vcd-units"
scopes=$(grep -oE '^\$scope module [a-z]+' "$tmp/v.vcd" | awk '{ print $3 }' | tr '\n' ' ')
[[ $scopes == 'albatros engine pipe ' ]] && ok || bad "vp trace of pipe,engine has scopes: $scopes"
"$bin" vp "$tmp/two.stream" --profile t32 --fidelity cycle -q --vcd "$tmp/vall.vcd" && ok || bad "vp trace"
for u in engine pipe; do
    cmp -s <(changes $u "$tmp/vall.vcd") <(changes $u "$tmp/v.vcd") && ok || bad "vp: $u changes differ"
done

# --vcd-window A:B: the trace starts at cycle A with every signal's real
# value ($dumpvars, not reset zeros) and ends at the end of cycle B, and at
# every time between it holds what the whole run's trace holds
"$bin" scene random --faces 30 --seed 7 -o "$tmp/r.scene"
"$bin" render "$tmp/r.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/all.vcd" &&
    "$bin" render "$tmp/r.scene" --profile t32 --fidelity cycle -q --vcd "$tmp/win.vcd" --vcd-window 300:700 &&
    ok || bad "window traces"
python3 - "$tmp/all.vcd" "$tmp/win.vcd" 300 700 <<'PYEOF' && ok || bad "the windowed trace is not the whole trace's window"
import sys
def parse(path):
    """(dumpvars time, dumpvars values, [(time, id, value)] after it, every time)"""
    ids, changes, times, dump, dump_t, t, in_dump = set(), [], [], {}, None, None, False
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == '$var':
            ids.add(w[3])
        elif w[0] == '$dumpvars':
            in_dump, dump_t = True, t
        elif w[0] == '$end' and in_dump:
            in_dump = False
        elif w[0].startswith('#'):
            t = int(w[0][1:])
            times.append(t)
        elif w[0][0] in '01' or w[0][0] == 'b':
            val, ident = (w[0][1:], w[1]) if w[0][0] == 'b' else (w[0][0], w[0][1:])
            (dump.__setitem__(ident, int(val, 2)) if in_dump else changes.append((t, ident, int(val, 2))))
    return ids, dump_t, dump, changes, times
ids_a, ta, da, ca, times_a = parse(sys.argv[1])
ids_w, tw, dw, cw, times_w = parse(sys.argv[2])
a, b = int(sys.argv[3]), int(sys.argv[4])
# the whole trace's clock: a rising edge each cycle, times cycle * period
period = sorted(set(x for x in times_a))[2]   # 0, period/2, period
def state(d, changes, until):
    s = dict(d)
    for t, i, v in changes:
        if t > until:
            break
        s[i] = v
    return s
err = []
if tw != a * period: err.append('window starts at %s, not %d' % (tw, a * period))
if max(times_w) != (b + 1) * period: err.append('ends at %d, not %d' % (max(times_w), (b + 1) * period))
if min(times_w) < a * period: err.append('a time before the window')
if set(dw) != ids_w: err.append('$dumpvars lacks %s' % sorted(ids_w - set(dw)))
for t in sorted(set(times_w))[:-1]:   # the last is the end of cycle B, no change
    sa, sw = state(da, ca, t), state(dw, cw, t)
    bad = [i for i in ids_w if sa.get(i, 0) != sw.get(i, 0)]
    if bad:
        err.append('at %d: %s differ' % (t, bad[:5]))
        break
# the window must show something the reset state does not
if all(v == 0 for i, v in dw.items() if i != '!'): err.append('$dumpvars all zeros')
print('\n'.join(err))
sys.exit(1 if err else 0)
PYEOF

finish
