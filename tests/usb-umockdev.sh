#!/usr/bin/env bash
# usb-umockdev.sh BUILD [ALBATROS] — the USB transport against a board that exists only
# in sysfs and /dev, mocked by umockdev (no hardware, no kernel module, no
# root): enumeration finds our board by its descriptors and ignores other
# devices; what needs real transfers (HID reports, bulk) fails with a clear
# message and exit status instead of hanging or crashing.  umockdev can replay
# transfers only from a recording of real hardware, which this repository
# does not have (docs/usb-protocol.md, "Testing without hardware").
# Ends with "N passed, N failed".
set -u
build=${1:-build}
bin=${2:-$build/albatros}   # make memcheck passes a valgrind wrapper
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
if ! command -v umockdev-run > /dev/null; then
    echo "FAIL: umockdev-run not found: install umockdev (make setup)" >&2
    echo "0 passed, 1 failed"
    exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
desc=$("$build/tests/usb_descriptors") || { echo "0 passed, 1 failed"; exit 1; }

# a USB device node as udev and sysfs describe it; VID:PID from the descriptors
device() {   # device FILE DESCRIPTORS
    cat > "$1" <<EOT
P: /devices/pci0000:00/0000:00:14.0/usb1/1-1
N: bus/usb/001/002=$2
E: DEVNAME=/dev/bus/usb/001/002
E: DEVTYPE=usb_device
E: DRIVER=usb
E: SUBSYSTEM=usb
E: BUSNUM=001
E: DEVNUM=002
A: busnum=1
A: devnum=2
A: bConfigurationValue=1
A: bNumConfigurations=1
A: speed=480
H: descriptors=$2
EOT
}
device "$tmp/board.umockdev" "$desc"
# the same device with another vendor id (bytes 8..9 of the device descriptor)
device "$tmp/other.umockdev" "${desc:0:16}3412${desc:20}"

# umockdev works by LD_PRELOAD, ahead of the sanitizers' runtime in an ASan
# build (make asan): tell ASan that this order is intended
export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0
run() { umockdev-run --device "$1" -- "${@:2}" > "$tmp/out" 2>&1; }

run "$tmp/board.umockdev" "$bin" board list
[[ $? -eq 0 ]] && grep -qE '^usb:001:002  1209:0001' "$tmp/out" && ok || bad "board list: $(cat "$tmp/out")"
run "$tmp/other.umockdev" "$bin" board list
[[ $? -eq 0 ]] && grep -q 'no board 1209:0001 on the USB bus' "$tmp/out" && ok || bad "other device listed: $(cat "$tmp/out")"
run "$tmp/other.umockdev" "$bin" board list --vid 0x1234 --pid 0x0001
[[ $? -eq 0 ]] && grep -qE '^usb:001:002  1234:0001' "$tmp/out" && ok || bad "--vid: $(cat "$tmp/out")"
# no transfers behind the mock: a clear error, the link-failure status
run "$tmp/board.umockdev" timeout 60 "$bin" board info
rc=$?
[[ $rc -eq 1 ]] && grep -q '^albatros board: .*LIBUSB_ERROR' "$tmp/out" && ok || bad "board info: exit $rc: $(cat "$tmp/out")"
run "$tmp/board.umockdev" timeout 60 "$bin" stream --profile a256 --timeout 200
rc=$?
[[ $rc -eq 3 ]] && grep -q '^albatros stream: .*LIBUSB_ERROR' "$tmp/out" && ok || bad "stream: exit $rc: $(cat "$tmp/out")"
run "$tmp/other.umockdev" timeout 60 "$bin" stream --profile a256 --timeout 200
rc=$?
[[ $rc -eq 3 ]] && grep -q 'opening USB device 1209:0001: .*is the board plugged in' "$tmp/out" && ok || bad "stream, no board: exit $rc: $(cat "$tmp/out")"
echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
