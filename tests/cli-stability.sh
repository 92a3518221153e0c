#!/usr/bin/env bash
# cli-stability.sh ALBATROS — albatros stability, scene FAMILY and method at
# a tiny profile (t32): job lines that carry the profile, progress in logs,
# the report's CSVs, Markdown and charts, the make sweep rules
# (docs/stability.md, docs/methods.md).
source "$(dirname "$0")/lib.sh"
root=$(cd "$(dirname "$0")/.." && pwd)

# --jobs: every job line carries the options that change a result
"$bin" stability --jobs --set depth_bits=16 --seeds 3 --out "$tmp/j" > "$tmp/jobs.txt"
[[ $(wc -l < "$tmp/jobs.txt") -eq 11 && $(grep -c -- '--profile a256 --set depth_bits=16 ' "$tmp/jobs.txt") -eq 11 ]] \
    && ok || bad "job lines lack the --set: $(cat "$tmp/jobs.txt")"
[[ $(grep -- '--family' "$tmp/jobs.txt" | grep -c -- '--seeds 3 ') -eq 10 ]] && grep -q -- '--speed$' "$tmp/jobs.txt" \
    && ok || bad "job lines: $(cat "$tmp/jobs.txt")"
expect 0 "--profile t32 --set aa=0 --size 32x32 -q --seeds 1 --out .* --family cyclic" \
    "$bin" stability --jobs --profile t32 --set aa=0 --size 32x32 -q --seeds 1 --out "$tmp/st"
# a printed job line runs as it stands, from anywhere: it names this program
# by its absolute path (it was not found on PATH)
line=$("$bin" stability --jobs --profile t32 --seeds 1 --out "$tmp/st" | grep -- '--family cyclic')
[[ $line == /* ]] && ok || bad "job line does not start with an absolute path: $line"
(cd / && eval "$line") 2> "$tmp/progress.txt" && [[ $(wc -l < "$tmp/st/stability-cyclic.csv") -eq 69 ]] \
    && ok || bad "job line '$line' failed or wrote $(wc -l < "$tmp/st/stability-cyclic.csv") lines"
# not on a terminal: one progress line per severity; -q: none
[[ $(grep -c '^stability cyclic: severity [1-4]/4 .* done' "$tmp/progress.txt") -eq 4 ]] \
    && ok || bad "progress in a log: $(cat "$tmp/progress.txt")"
"$bin" stability -q --profile t32 --seeds 1 --family cyclic --out "$tmp/st" 2> "$tmp/quiet.txt"
[[ ! -s $tmp/quiet.txt ]] && ok || bad "-q printed: $(cat "$tmp/quiet.txt")"

# --report without speed.csv names only what it wrote
expect 0 "wrote .*stability.png" "$bin" stability --report --out "$tmp/st"
"$bin" stability --report --out "$tmp/st" | grep -q speed && bad "--report claims speed files" || ok
[[ ! -e $tmp/st/speed.md && ! -e $tmp/st/speed.png ]] && ok || bad "speed files without speed.csv"

# the merged CSV counts failures: at 10^40 the GP refuses both seeds
"$bin" stability -q --profile t32 --seeds 2 --family coords --out "$tmp/st" &&
    "$bin" stability -q --report --out "$tmp/st" &&
    grep -q '^coords,4,40,vp,,,,2$' "$tmp/st/stability.csv" && grep -q '^coords,4,40,vp,,,,2$' "$tmp/st/stability-coords.csv" \
    && ok || bad "failed count: $(grep '^coords,4,40,vp,' "$tmp/st/stability.csv" "$tmp/st/stability-coords.csv")"

# the speed sweep at t32: CSV (with the reference timed), Markdown with a Pareto front, PNG
expect 0 "" "$bin" stability --speed --profile t32 --out "$tmp/st"
[[ $(head -1 "$tmp/st/speed.csv") == config,fidelity,scenes,face_diff_pct,ms_per_frame,failed ]] \
    && grep -q '^reference,-,18,0.0000,' "$tmp/st/speed.csv" && grep -q '^vp-aa1,functional,18,' "$tmp/st/speed.csv" \
    && ok || bad "speed.csv: $(cat "$tmp/st/speed.csv")"
expect 0 "wrote .*speed.md, .*speed.png" "$bin" stability --report --out "$tmp/st"
grep -q '| yes |$' "$tmp/st/speed.md" && ok || bad "speed.md has no Pareto front row"
[[ $(head -c 8 "$tmp/st/speed.png" | od -An -tx1 | tr -d ' ') == 89504e470d0a1a0a ]] && ok || bad "speed.png is not a PNG"

# make sweep reruns the jobs even where every CSV is newer than the binary
if command -v make > /dev/null; then
    mkdir -p "$tmp/mk"
    for f in sliver crossing-z0 far texture-far interpenetrating cyclic degenerate tjunction deep coords; do
        touch "$tmp/mk/stability-$f.csv"
    done
    touch "$tmp/mk/speed.csv"
    absbin=$(realpath "$bin")
    make -C "$root" -n -s -o "$absbin" ALBATROS="$absbin" SWEEP_DIR="$tmp/mk" sweep > "$tmp/make.txt" 2>&1
    [[ $(grep -c -- 'stability --family' "$tmp/make.txt") -eq 10 ]] && grep -q -- 'stability --speed' "$tmp/make.txt" \
        && ok || bad "make sweep does not rerun the jobs: $(cat "$tmp/make.txt")"
fi

# scene FAMILY: a stress scene at a severity, seeded
expect 0 "" "$bin" scene cyclic --severity 0.3 --seed 2 -o "$tmp/c.scene"
grep -q '^# stress cyclic severity 0.29999' "$tmp/c.scene" && ok || bad "scene cyclic header: $(head -2 "$tmp/c.scene")"
"$bin" scene cyclic --severity 0.3 --seed 2 | cmp -s - "$tmp/c.scene" && ok || bad "scene cyclic not deterministic"
"$bin" scene cyclic --severity 0.3 --seed 3 | cmp -s - "$tmp/c.scene" && bad "the seed changes nothing" || ok
expect 0 "# stress tjunction severity 64 " "$bin" scene tjunction --severity 1000
expect 2 "give --severity" "$bin" scene far
expect 2 "--severity is for the stress families" "$bin" scene random --severity 2
expect 2 "unknown kind 'nope'" "$bin" scene nope
expect 0 "FAMILY --severity" "$bin" scene --help

# method: one classic method to EXR/PNG, for compare
expect 0 "usage: albatros method" "$bin" method --help
expect 0 "painter .*cyclic overlap" "$bin" method --list
expect 2 "unknown method 'nope'" "$bin" method nope "$tmp/c.scene" -o "$tmp/x.exr"
expect 2 "nothing to write" "$bin" method zbuffer "$tmp/c.scene"
expect 2 "aa=0" "$bin" method zbuffer "$tmp/c.scene" --profile t32 --set aa=1 -o "$tmp/x.exr"
expect 0 "painter frame 0" "$bin" method painter "$tmp/c.scene" --profile t32 -o "$tmp/p.exr" --png "$tmp/p.png"
expect 0 "" "$bin" method zbuffer "$tmp/c.scene" --profile t32 -o "$tmp/z.exr"
expect 0 "" "$bin" reference -q "$tmp/c.scene" --profile t32 -o "$tmp/r.exr"
[[ $(head -c 8 "$tmp/p.png" | od -An -tx1 | tr -d ' ') == 89504e470d0a1a0a ]] && ok || bad "method --png is not a PNG"
# the painter paints one crossing in the wrong order; the z-buffer does not
expect 1 "1024 pixels: [1-9][0-9]* with a different face" "$bin" compare "$tmp/r.exr" "$tmp/p.exr"
expect 0 "1024 pixels: 0 with a different face" "$bin" compare "$tmp/r.exr" "$tmp/z.exr"

# the charts read right (docs/stability.md): every panel's axes say what
# they measure, no two series share a colour, a family where nothing differs
# is named rather than drawn flat, and the speed chart labels its points by
# number with the names in its key
mkdir -p "$tmp/rep"
cp docs/stability/stability-*.csv docs/stability/speed.csv "$tmp/rep/" 2>/dev/null ||
    cp "$(dirname "$0")"/../docs/stability/stability-*.csv "$(dirname "$0")"/../docs/stability/speed.csv "$tmp/rep/"
if "$bin" stability --report --out "$tmp/rep" -q > /dev/null 2>&1; then ok; else bad "stability --report"; fi
gp=$tmp/rep/stability.gp
panels=$(grep -c '^set title' "$gp")
[[ $(grep -c "^set xlabel 'severity: [a-z]" "$gp") -eq $((panels - 1)) && $(grep -c "^set ylabel 'pixels wrong, %'" "$gp") -eq 1 ]] &&
    ok || bad "stability panels without axis labels: $(grep -c '^set xlabel' "$gp") of $panels"
colours=$(grep -o "^set linetype [0-9]* lc rgb '#[0-9a-f]*'" "$gp" | awk '{print $6}')
[[ $(wc -l <<<"$colours") -eq 17 && $(sort -u <<<"$colours" | wc -l) -eq 17 ]] && ok ||
    bad "stability series colours: $(sort <<<"$colours" | uniq -d | tr '\n' ' ') repeat"
grep -q "no configuration differs anywhere on: texture-far" "$gp" && ! grep -q "^set title 'texture-far'" "$gp" &&
    ok || bad "a flat panel is drawn"
[[ $(grep -o "ls [0-9]* title '[^']*'" "$gp" | wc -l) -eq 17 ]] && ok || bad "the legend lacks series"
spd=$tmp/rep/speed-points.dat
[[ $(awk -F'"' 'NF > 4 && $4 !~ /^[0-9,]*$/' "$spd" | wc -l) -eq 0 && $(grep -c "keyentry" "$tmp/rep/speed.gp") -eq $(grep -c . "$tmp/rep/speed.csv" | awk '{print $1 - 1}') ]] &&
    ok || bad "speed chart points not numbered, or the key incomplete"
grep -q "set xlabel 'host time per frame, ms" "$tmp/rep/speed.gp" && ok || bad "speed chart x axis"
# a failed gnuplot run keeps the last good chart and leaves no temporary
cp "$tmp/rep/stability.png" "$tmp/good.png"
PATH=/nonexistent "$bin" stability --report --out "$tmp/rep" -q > /dev/null 2>&1
[[ $? -ne 0 ]] && cmp -s "$tmp/rep/stability.png" "$tmp/good.png" && ! compgen -G "$tmp/rep/.*.tmp" > /dev/null &&
    ok || bad "a failed chart run replaced or left files"

finish
