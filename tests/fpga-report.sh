#!/usr/bin/env bash
# fpga-report.sh — make test's fast check of the FPGA report judge
# (rtl/fpga/fpga_report.py, docs/fpga.md).  The committed report of the real
# flow (docs/fpga/report.json: the flat build placed and routed on the HX8K
# breakout) must be judged to fit and meet both clocks; the UP5K's packed
# report of the same build (docs/fpga/pack-report-icebreaker.json, 108% of its
# logic cells, never placed) must be judged not to; the HX8K's report planted
# one logic cell or one block RAM over, or with the VP's clock below the
# profile's, must fail; without its fmax section or cut off it is an input
# error (exit 2).  The real flow is make fpga-check.
set -u
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok   $1"; }
bad() { fail=$((fail + 1)); echo "FAIL $1"; }
judge=rtl/fpga/fpga_report.py
rep=docs/fpga/report.json
khz=$(sed -n 's/.*"clock_khz": *\([0-9]*\).*/\1/p' docs/fpga/flow.json)
[[ -n $khz ]] || { bad "docs/fpga/flow.json: no clock_khz"; echo "$pass passed, $fail failed"; exit 1; }
mhz=$(awk -v k="$khz" 'BEGIN { print k / 1000 }')
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

expect() {   # WHAT STATUS REPORT
    local what=$1 want=$2 r=$3 got
    python3 "$judge" "$r" --clock clk_vp="$mhz" --clock ifclk=48 > "$tmp/out" 2>&1
    got=$?
    if [[ $got -eq $want ]]; then ok "$what (exit $got)"; else bad "$what: exit $got, expected $want"; sed 's/^/     /' "$tmp/out"; fi
}
expect "the committed report (the flat build on the HX8K, placed) fits and meets its clocks" 0 "$rep"
expect "the UP5K's packed report of the same build (logic cells over, not placed) is rejected" 1 \
    docs/fpga/pack-report-icebreaker.json
python3 - "$rep" "$tmp" <<'PY'
import json, sys
rep = json.load(open(sys.argv[1]))
def planted(name, edit):
    r = json.loads(json.dumps(rep))
    edit(r)
    json.dump(r, open(sys.argv[2] + "/" + name + ".json", "w"))
def over(res):
    def edit(r):
        r["utilization"][res]["used"] = r["utilization"][res]["available"] + 1
    return edit
planted("over", over("ICESTORM_LC"))
planted("ram", over("ICESTORM_RAM"))
def slow(r):
    (k,) = [k for k in r["fmax"] if k.startswith("clk_vp")]
    r["fmax"][k]["achieved"] = 11.9
planted("slow", slow)
planted("nofmax", lambda r: r.pop("fmax"))
PY
expect "planted one logic cell over the part, rejected" 1 "$tmp/over.json"
expect "planted one block RAM over the part, rejected" 1 "$tmp/ram.json"
expect "planted with the VP's clock at 11.9 MHz, rejected" 1 "$tmp/slow.json"
expect "planted without its fmax section, an input error" 2 "$tmp/nofmax.json"
echo '{"utilization": ' > "$tmp/cut.json"
expect "a cut-off report, an input error" 2 "$tmp/cut.json"
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
