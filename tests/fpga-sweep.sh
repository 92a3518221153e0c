#!/usr/bin/env bash
# fpga-sweep.sh [ALBATROS] — make test's fast check of the design-space view
# (docs/fpga.md, make fpga-sweep; the synthesis itself is minutes, not run
# here).  The committed docs/fpga/sweep.csv has the collect script's columns
# and a row of as many fields for every point of rtl/fpga/fpga.mk; its a512
# row's cycles per frame are the cycle model's, recomputed now (mean over the
# frames, computed here in awk); a planted wrong cycle count is caught.
# rtl/fpga/sweep_units.py gives each unit the parameter names alb_vp's
# instance sets (read from rtl/alb_vp.sv).  The collect script rejects,
# naming file and line, a missing unit output, a malformed field, a unit
# output of another unit and a cycles line without a scene.
set -u
bin=${1:-build/albatros}
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
csv=docs/fpga/sweep.csv
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
units=$(make -s --no-print-directory -f - <<< 'include rtl/fpga/fpga.mk
show: ; @echo $(FPGA_SWEEP_UNITS)' show)
families=$(sed -n 's/^FPGA_SWEEP_FAMILIES := *//p' rtl/fpga/fpga.mk)
severity=$(sed -n 's/^FPGA_SWEEP_SEVERITY := *//p' rtl/fpga/fpga.mk)
points=$(sed -n '/^FPGA_SWEEP_POINTS :=/,/[^\\]$/p' rtl/fpga/fpga.mk | sed 's/^FPGA_SWEEP_POINTS :=//' |
         tr -d '\\' | tr -s ' \n' ' ')

# ---- the committed CSV: header, one row per point, as many fields ----
want="point,profile,sets,width,height,edge_units,fill_rate,face_slots,fill_queue,fifo_depth"
for u in $units; do want="$want,cells_${u#alb_}"; done
want="$want,cells_total,memory_bits,synth_cpu_seconds,cycles_builtin"
for f in $families; do want="$want,cycles_$f"; done
if [[ $(head -1 "$csv") == "$want" ]]; then ok "$csv: the columns of the units and scenes"
else bad "$csv: header $(head -1 "$csv"), expected $want"; fi
names=$(for p in $points; do echo "${p%%:*}"; done)
if [[ $(tail -n +2 "$csv" | cut -d, -f1) == "$names" ]]; then ok "$csv: a row per point of fpga.mk"
else bad "$csv: rows $(tail -n +2 "$csv" | cut -d, -f1 | tr '\n' ' '), expected $names"; fi
ncol=$(head -1 "$csv" | awk -F, '{ print NF }')
if awk -F, -v n="$ncol" 'NR > 1 && NF != n { exit 1 }' "$csv"; then ok "$csv: $ncol fields in every row"
else bad "$csv: a row without $ncol fields"; fi
if awk -F, -v n="$ncol" 'NR > 1 { s = 0; for (i = 11; i < 11 + '"$(wc -w <<< "$units")"'; i++) s += $i
                         if (s != $(i)) exit 1 }' "$csv"; then ok "$csv: cells_total is the sum of the units"
else bad "$csv: a cells_total that is not the sum of its units"; fi

# ---- the a512 row's cycles against the model ----
mean() {   # SCENE... : the model's cycles per frame, mean of the frames, rounded
    "$bin" render "$@" --profile a512 --fidelity cycle --json 2> /dev/null |
        grep -o '"timing": {"cycles": [0-9]*' | awk '{ s += $NF; n++ } END { if (n) printf "%d\n", int(s / n + 0.5) }'
}
model="$(mean)"
for f in $families; do
    "$bin" scene "$f" --severity "$severity" -o "$tmp/$f.scene" > /dev/null 2>&1
    model="$model,$(mean "$tmp/$f.scene")"
done
cyc() { awk -F, -v n="$ncol" -v k="$(wc -w <<< "$families")" '$1 == "a512" {
            s = $(n - k); for (i = n - k + 1; i <= n; i++) s = s "," $i; print s }' "$1"; }
if [[ $(cyc "$csv") == "$model" ]]; then ok "$csv: a512's cycles per frame are the model's ($model)"
else bad "$csv: a512's cycles $(cyc "$csv"), the model's now $model"; fi
awk -F, -v n="$ncol" 'BEGIN { OFS = "," } $1 == "a512" { $n = $n + 1 } { print }' "$csv" > "$tmp/planted.csv"
if [[ $(cyc "$tmp/planted.csv") != "$model" ]]; then ok "a planted cycle count (one more) is caught"
else bad "a planted cycle count passed"; fi

# ---- docs/fpga.md's headline figures are the CSV's ----
col() { awk -F, -v p="$1" -v c="$2" 'NR == 1 { for (i = 1; i <= NF; i++) k[$i] = i; next }
                                    $1 == p { print $(k[c]) }' "$csv"; }
eu="$(col a512-eu1 cycles_builtin), $(col a512-eu2 cycles_builtin), $(col a512-eu4 cycles_builtin), $(col a512 cycles_builtin), $(col a512-eu16 cycles_builtin)"
fr="$(col a512-fr1 cycles_builtin) to $(col a512-fr8 cycles_builtin) cycles, $(col a512-fr1 cells_total) to $(col a512-fr8 cells_total) cells"
text=$(sed -n '/^## The design-space view/,/^## /p' docs/fpga.md | tr '\n' ' ' | tr -s ' ')
for want in "1, 2, 4, 8, 16 take $eu cycles" "1 to 8: $fr" \
            "$(col a1024 cycles_builtin) cycles on the built-in scene with $(col a1024 cells_total) cells"; do
    if [[ $text == *"$want"* ]]; then ok "docs/fpga.md says '$want'"
    else bad "docs/fpga.md's design-space view lacks '$want' (the CSV's figures)"; fi
done

# ---- the units' parameter names are alb_vp's ----
for u in $(python3 rtl/fpga/sweep_units.py --list); do
    from_vp=$(awk -v u="$u" '$1 == u && $2 ~ /^#/ { on = 1 } on { print } on && /\) *u_/ { exit }' rtl/alb_vp.sv |
              grep -o '\.[A-Z_]*(' | tr -d '.(' | sort | tr '\n' ' ')
    ours=$(python3 rtl/fpga/sweep_units.py "$u" $(rtl/profile-params.sh --albatros "$bin" --format shell t32) |
           grep -o 'chparam [A-Z_]*' | cut -d' ' -f2 | sort | tr '\n' ' ')
    if [[ -n $from_vp && $from_vp == "$ours" ]]; then ok "$u: the parameters alb_vp sets ($from_vp)"
    else bad "$u: sweep_units.py sets '$ours', alb_vp's instance '$from_vp'"; fi
done

# ---- the collect script on planted job outputs ----
d=$tmp/jobs
mkdir -p "$d/p1"
printf 'WIDTH=32\nHEIGHT=32\nEDGE_UNITS=8\nFILL_RATE=4\nFACE_SLOTS=2\nFILL_QUEUE=4\nFIFO_DEPTH=512\n' > "$d/p1/params"
for u in $units; do echo "unit=$u cells=10 memory_bits=5 memories=1 seconds=2 cpu_seconds=1 abc=1" > "$d/p1/$u.unit"; done
line="builtin=100"; for f in $families; do line="$line $f=7"; done; echo "$line" > "$d/p1/cycles"
collect() { python3 rtl/fpga/sweep_collect.py "$d" --units "$units" --families "$families" p1:t32 > "$tmp/out.csv" 2> "$tmp/err"; }
nu=$(wc -w <<< "$units")
if collect && [[ $(sed -n 2p "$tmp/out.csv") == p1,t32,,32,32,8,4,2,4,512,*,$((10 * nu)),$((5 * nu)),$nu,100,7,7 ]]
then ok "collect: a good point gives its row"; else bad "collect on a good point: $(cat "$tmp/out.csv" "$tmp/err")"; fi
reject() {   # WHAT PATTERN
    if collect; then bad "collect accepted $1"
    elif grep -q -- "$2" "$tmp/err"; then ok "collect rejects $1: $(cat "$tmp/err")"
    else bad "collect on $1: message $(cat "$tmp/err"), expected /$2/"; fi
}
first=${units%% *}
mv "$d/p1/$first.unit" "$tmp/saved"
reject "a missing unit output" "p1/$first.unit: No such file"
sed 's/cells=10/cells=ten/' "$tmp/saved" > "$d/p1/$first.unit"
reject "a malformed cell count" "p1/$first.unit:1: cells='ten'"
sed "s/unit=$first/unit=alb_other/" "$tmp/saved" > "$d/p1/$first.unit"
reject "another unit's output" "p1/$first.unit:1: unit='alb_other'"
mv "$tmp/saved" "$d/p1/$first.unit"
echo "builtin=100" > "$d/p1/cycles"
reject "a cycles line without its scenes" "p1/cycles:1: no ${families%% *}="
: > "$d/p1/cycles"
reject "an empty cycles output" "p1/cycles: empty"
echo "$pass passed, $fail failed"
[[ $fail -eq 0 && $pass -gt 0 ]]
