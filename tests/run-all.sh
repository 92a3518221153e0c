#!/usr/bin/env bash
# run-all.sh BUILD [--memcheck] — every test runner of the project, then the
# total.  Each runner ends with "N passed, N failed"; this sums them.
# --memcheck: the unit tests, the fuzz harnesses and every albatros process
# of the other runners under valgrind (the firmware runner builds with sdcc
# and runs nothing of ours).
set -u
build=${1:-build}
bin=$build/albatros unit=()
if [[ ${2:-} == --memcheck ]]; then
    vg=(valgrind -q --error-exitcode=99 --leak-check=full --errors-for-leak-kinds=definite,indirect
        --show-leak-kinds=definite,indirect)
    bin=$(mktemp)
    printf '#!/bin/sh\nexec %s "%s" "$@"\n' "${vg[*]}" "$(realpath "$build/albatros")" > "$bin"
    chmod +x "$bin"
    unit=("${vg[@]}")
    # for runners that need the program itself (cachegrind counts, short runs)
    export ALBATROS_UNWRAPPED=$(realpath "$build/albatros")
fi
total_pass=0 total_fail=0 status=0
log=$(mktemp)
trap 'rm -f "$log"; [[ $bin != "$build/albatros" ]] && rm -f "$bin"' EXIT
run() {
    local name=$1; shift
    echo "== $name: $*"
    "$@" 2>&1 | tee "$log"
    local rc=${PIPESTATUS[0]}
    local out
    out=$(tail -n 1 "$log")
    if [[ $out =~ ^([0-9]+)\ passed,\ ([0-9]+)\ failed$ ]]; then
        total_pass=$((total_pass + BASH_REMATCH[1]))
        total_fail=$((total_fail + BASH_REMATCH[2]))
        [[ ${BASH_REMATCH[1]} -eq 0 ]] && status=1
    else
        echo "$name: no summary line (exit $rc)"
        total_fail=$((total_fail + 1))
    fi
    [[ $rc -ne 0 ]] && status=1
}
run unit "${unit[@]}" "$build/tests/unit" --bindir "$build"
run cli bash tests/cli.sh "$bin"
for t in tests/cli-*.sh; do   # one per area: cli-stream.sh, cli-stability.sh, ...
    [[ -e $t ]] && run "$(basename "$t" .sh)" bash "$t" "$bin"
done
run vectors "$bin" vectors check test-vectors
run malformed bash tests/malformed.sh "$bin"
run doc-numbers bash tests/doc-numbers.sh "$bin" "$build"
run fuzz-replay bash tests/fuzz-replay.sh "$build" "${unit[@]}"
run firmware bash tests/firmware.sh "$build"
run firmware-s51 bash tests/firmware-s51.sh "$build" "${unit[@]}"
run dpi bash tests/dpi.sh "$build"
run python bash tests/python.sh "$build"
run install bash tests/install.sh "$build"
run usb-umockdev bash tests/usb-umockdev.sh "$build" "$bin"
run cosim bash tests/cosim.sh "$build"
run fpga-report bash tests/fpga-report.sh
run fpga-top bash tests/fpga-top.sh "$build"
run fpga-sweep bash tests/fpga-sweep.sh "$bin"
echo "$total_pass passed, $total_fail failed"
[[ $status -eq 0 && $total_fail -eq 0 ]]
