#!/usr/bin/env bash
# firmware.sh BUILD — the FX2LP firmware builds with sdcc and fits the chip:
# code and external data within its 16 KB of RAM (docs/usb-protocol.md).
set -u
build=${1:-build}
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
if ! command -v sdcc >/dev/null; then
    bad "sdcc is not installed (apt-get install sdcc; make setup does)"
else
    out=$(make -s BUILD="$build" firmware 2>&1) && ok || bad "make firmware: $out"
    size=$(make -s BUILD="$build" firmware-size 2>&1) && ok || bad "firmware too large: $size"
    echo "$size"
    [[ $size =~ total\ ([0-9]+)\ of\ 16384 ]] && (( BASH_REMATCH[1] <= 16384 )) && ok || bad "size line: $size"
fi
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
