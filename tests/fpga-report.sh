#!/usr/bin/env bash
# fpga-report.sh — make test's fast check of the FPGA report judge
# (rtl/fpga/fpga_report.py, docs/fpga.md): the committed report of the real
# flow (docs/fpga/report.json) passes; planted reports must fail — one over
# the part's logic cells, one below the VP's clock, one with the fmax
# section missing (an input error, exit 2).  The real flow is make fpga-check.
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
expect "the committed report fits and meets $mhz MHz" 0 "$rep"
python3 - "$rep" "$tmp" <<'PY'
import json, sys
rep = json.load(open(sys.argv[1]))
over = json.loads(json.dumps(rep))
lc = over["utilization"]["ICESTORM_LC"]
lc["used"] = lc["available"] + 1
json.dump(over, open(sys.argv[2] + "/over.json", "w"))
slow = json.loads(json.dumps(rep))
for name in slow["fmax"]:
    if "clk_vp" in name:
        slow["fmax"][name]["achieved"] = 1.0
json.dump(slow, open(sys.argv[2] + "/slow.json", "w"))
nofmax = json.loads(json.dumps(rep))
del nofmax["fmax"]
json.dump(nofmax, open(sys.argv[2] + "/nofmax.json", "w"))
PY
expect "a report one logic cell over the part is rejected" 1 "$tmp/over.json"
expect "a report whose VP clock is 1 MHz is rejected" 1 "$tmp/slow.json"
expect "a report without its fmax section is an input error" 2 "$tmp/nofmax.json"
echo '{"utilization": ' > "$tmp/cut.json"
expect "a cut-off report is an input error" 2 "$tmp/cut.json"
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
