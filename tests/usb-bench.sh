#!/usr/bin/env bash
# usb-bench.sh BUILD — bulk OUT throughput through libusb on the emulated
# bus (make usb-bench; docs/usb-protocol.md, "Throughput"): MB/s against the
# number of transfers in flight and their size, with the bus unpaced (what
# the path itself costs: libusb, the usbfs ioctls umockdev forwards, the
# board's firmware core) and paced at 40 MB/s in 1 ms steps (about what a
# high-speed bulk endpoint moves), where too few transfers leave the bus
# idle.  The board is the firmware core alone (--sink: no VP).  Three runs
# a cell, the median shown; all of them in BUILD/usb-bench.csv.
set -eu
build=${1:-build}
board=$build/tests/usb_board bench=$build/tests/usb_bench
csv=$build/usb-bench.csv
transfers=(1 2 4 8 16 32)
buffers=(512 4096 16384 65536 262144)
echo "bus,transfers,buffer,payload,mb,seconds,mbps" > "$csv"
for bus in 0 40; do
    printf '\n%s\n\n| transfers in flight |' "$([[ $bus == 0 ]] && echo "unpaced bus (MB/s)" ||
        echo "bus paced at $bus MB/s (MB/s)")"
    for b in "${buffers[@]}"; do printf ' %s B |' "$b"; done
    printf '\n|---|'
    for b in "${buffers[@]}"; do printf -- '---|'; done
    printf '\n'
    for n in "${transfers[@]}"; do
        printf '| %s |' "$n"
        for b in "${buffers[@]}"; do
            mb=$(( b < 4096 ? 2 : b < 65536 ? 4 : 16 ))
            runs=()
            for r in 1 2 3; do
                line=$(umockdev-wrapper "$board" --sink --bus-mbps "$bus" -- \
                       "$bench" --transfers "$n" --buffer "$b" --mb "$mb" 2> "$build/usb-bench.err") || {
                    echo "usb-bench: $n x $b: $(cat "$build/usb-bench.err")" >&2
                    exit 1
                }
                echo "$bus,$line" >> "$csv"
                runs+=("${line##*,}")
            done
            # the median of three: the machine is shared, single runs are noisy
            printf ' %s |' "$(printf '%s\n' "${runs[@]}" | sort -g | sed -n 2p)"
        done
        printf '\n'
    done
done
rm -f "$build/usb-bench.err"
echo
echo "(every run in $csv)"
