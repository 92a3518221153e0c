#!/usr/bin/env bash
# fpga-report.sh — make test's fast check of the FPGA report judge
# (rtl/fpga/fpga_report.py, docs/fpga.md).  The committed report of the real
# flow (docs/fpga/report.json, nextpnr --pack-only: the design is 2.5 times
# the UP5K's logic cells (its DSPs fit, 8 / 8), so it was never placed) must
# be judged not to fit;
# the same report planted to fit, with Fmax above both clocks, must pass;
# planted one logic cell or one DSP over, or below the VP's clock, it must fail; without its
# fmax section or cut off it is an input error (exit 2).  The real flow is
# make fpga-check.
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
expect "the committed report (logic cells over the part, not placed) is rejected" 1 "$rep"
python3 - "$rep" "$tmp" <<'PY'
import json, sys
rep = json.load(open(sys.argv[1]))
fits = json.loads(json.dumps(rep))
for u in fits["utilization"].values():
    u["used"] = min(u["used"], u["available"])
fits["fmax"] = {"clk_vp$SB_IO_IN_$glb_clk": {"achieved": 20.5, "constraint": 12.0},
                "ifclk$SB_IO_IN_$glb_clk": {"achieved": 60.0, "constraint": 48.0}}
json.dump(fits, open(sys.argv[2] + "/fits.json", "w"))
over = json.loads(json.dumps(fits))
over["utilization"]["ICESTORM_LC"]["used"] = over["utilization"]["ICESTORM_LC"]["available"] + 1
json.dump(over, open(sys.argv[2] + "/over.json", "w"))
dsp = json.loads(json.dumps(fits))
dsp["utilization"]["ICESTORM_DSP"]["used"] = dsp["utilization"]["ICESTORM_DSP"]["available"] + 1
json.dump(dsp, open(sys.argv[2] + "/dsp.json", "w"))
slow = json.loads(json.dumps(fits))
slow["fmax"]["clk_vp$SB_IO_IN_$glb_clk"]["achieved"] = 11.9
json.dump(slow, open(sys.argv[2] + "/slow.json", "w"))
nofmax = json.loads(json.dumps(fits))
del nofmax["fmax"]
json.dump(nofmax, open(sys.argv[2] + "/nofmax.json", "w"))
PY
expect "the report planted to fit, Fmax above both clocks, passes" 0 "$tmp/fits.json"
expect "planted one logic cell over the part, rejected" 1 "$tmp/over.json"
expect "planted one DSP over the part, rejected" 1 "$tmp/dsp.json"
expect "planted with the VP's clock at 11.9 MHz, rejected" 1 "$tmp/slow.json"
expect "planted without its fmax section, an input error" 2 "$tmp/nofmax.json"
echo '{"utilization": ' > "$tmp/cut.json"
expect "a cut-off report, an input error" 2 "$tmp/cut.json"
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
