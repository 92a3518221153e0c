#!/usr/bin/env bash
# usb-umockdev.sh BUILD [ALBATROS] — the USB transport through real libusb
# and hidapi, no hardware, no kernel module, no root needed:
#  * a board that exists only in sysfs and /dev (umockdev-run --device):
#    enumeration, and clean errors where nothing answers transfers;
#  * a board on an emulated bus (tests/usb_board.c under umockdev-wrapper:
#    usbfs and hidraw ioctls answered, the firmware core and the VP behind
#    the endpoints): every golden vector streamed with each frame's CRC and
#    cycles checked against the vector's own files, high and full speed,
#    zero-length and short packets, stalls, a board that NAKs past the
#    timeout, Ctrl-C, an unplug with the board coming back, permissions that
#    arrive late, the hidraw node late, short HID reports, no hidraw node;
#  * the board's checks firing on a host that breaks them (tests/usb_rogue.c).
# Every run through the emulated bus must also leave the board's counters
# clean (no bad CRC, gap, duplicate or garbage byte: nothing lost, repeated
# or reordered) and no VIOLATION (docs/usb-protocol.md, "Testing without
# hardware").  Ends with "N passed, N failed".
set -u
build=${1:-build}
bin=${2:-$build/albatros}   # make memcheck passes a valgrind wrapper
board=$build/tests/usb_board shim=$build/tests/usb_access.so rogue=$build/tests/usb_rogue
pass=0 fail=0
ok()  { pass=$((pass + 1)); }
bad() { fail=$((fail + 1)); echo "FAIL: $*" >&2; }
for tool in umockdev-run umockdev-wrapper; do
    if ! command -v $tool > /dev/null; then
        echo "FAIL: $tool not found: install umockdev (make setup)" >&2
        echo "0 passed, 1 failed"
        exit 1
    fi
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
desc=$("$build/tests/usb_descriptors") || { echo "0 passed, 1 failed"; exit 1; }
# umockdev works by LD_PRELOAD, ahead of the sanitizers' runtime in an ASan
# build (make asan): tell ASan that this order is intended
export ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0
# and under make memcheck, what umockdev's preload does is not ours to fix
export VALGRIND_OPTS="${VALGRIND_OPTS:+$VALGRIND_OPTS }--suppressions=$(realpath "$(dirname "$0")")/usb-umockdev.supp"

# ---- a device in sysfs and /dev only: no transfers behind it ----

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
run() { umockdev-run --device "$1" -- "${@:2}" > "$tmp/out" 2>&1; }

run "$tmp/board.umockdev" "$bin" board list
[[ $? -eq 0 ]] && grep -qE '^usb:001:002  1209:0001' "$tmp/out" && ok || bad "board list: $(cat "$tmp/out")"
run "$tmp/other.umockdev" "$bin" board list
[[ $? -eq 0 ]] && grep -q 'no board 1209:0001 on the USB bus' "$tmp/out" && ok || bad "other device listed: $(cat "$tmp/out")"
run "$tmp/other.umockdev" "$bin" board list --vid 0x1234 --pid 0x0001
[[ $? -eq 0 ]] && grep -qE '^usb:001:002  1234:0001' "$tmp/out" && ok || bad "--vid: $(cat "$tmp/out")"
# no transfers behind this mock: a clear error, the link-failure status
run "$tmp/board.umockdev" timeout 60 "$bin" board info
rc=$?
[[ $rc -eq 1 ]] && grep -q '^albatros board: .*LIBUSB_ERROR' "$tmp/out" && ok || bad "board info: exit $rc: $(cat "$tmp/out")"
run "$tmp/board.umockdev" timeout 60 "$bin" stream --profile a256 --timeout 200
rc=$?
[[ $rc -eq 3 ]] && grep -q '^albatros stream: .*LIBUSB_ERROR' "$tmp/out" && ok || bad "stream: exit $rc: $(cat "$tmp/out")"
run "$tmp/other.umockdev" timeout 60 "$bin" stream --profile a256 --timeout 200
rc=$?
[[ $rc -eq 3 ]] && grep -q 'opening USB device 1209:0001: .*is the board plugged in' "$tmp/out" && ok || bad "stream, no board: exit $rc: $(cat "$tmp/out")"

# ---- the board on an emulated bus ----

# usb EXIT DESCRIPTION [BOARD OPTIONS] -- COMMAND...: the command under the
# board; its exit status and, unless the description starts with "!", a
# clean board (0 violations, nothing lost or repeated); then `has` checks
# its output.
usb() {
    local want=$1 what=$2
    shift 2
    local start=$SECONDS
    umockdev-wrapper "$board" --shim "$shim" --timeout 120 "$@" > "$tmp/out" 2>&1
    local rc=$?
    elapsed=$((SECONDS - start))
    last="$what"
    if [[ $rc -ne $want ]]; then
        bad "$what: exit $rc, expected $want: $(tail -n 12 "$tmp/out")"
        return 1
    fi
    if [[ $what != !* ]] && ! grep -qE '0 bad CRCs, 0 gaps, 0 duplicates, 0 garbage bytes, [0-9]+ frames, 0 dropped; 0 violations$' "$tmp/out"; then
        bad "$what: the board saw damage: $(grep -E 'usb_board' "$tmp/out" | tail -n 8)"
        return 1
    fi
    ok
}
has() {   # has PATTERN: the last usb run's output matches (extended regexp)
    grep -qE -- "$1" "$tmp/out" && ok || bad "$last: no /$1/ in: $(tail -n 12 "$tmp/out")"
}
hasnt() {
    grep -qE -- "$1" "$tmp/out" && bad "$last: /$1/ in: $(grep -E -- "$1" "$tmp/out" | head -3)" || ok
}

# every golden vector through real libusb: the host compares each frame's
# CRC and cycles with its emulator, the board (--golden) with the vector's
# expected.cycles and the frame stores of its expected.NNNN.exr
for v in test-vectors/*/; do
    v=${v%/}
    read -ra vopts < "$v/options"
    bopts=()   # the VP the board runs: the vector's profile and --set, not its GP options
    for ((i = 0; i < ${#vopts[@]}; i++)); do
        [[ ${vopts[i]} == --profile || ${vopts[i]} == --set ]] && bopts+=("${vopts[i]}" "${vopts[i + 1]}")
    done
    n=$(grep -c '^frame=' "$v/expected.cycles")
    usb 0 "golden vector $v" "${bopts[@]}" --golden "$v" -- "$bin" stream --stream "$v/expected.stream" "${vopts[@]}"
    has "stream: $n of $n frames match the emulator"
    has "usb_board: golden: $n of $n frames as $v has them"
done
# both checks catch a board that gets one bit of frame 2 wrong
usb 1 "!a wrong frame" --flip 2 --profile a512 --golden test-vectors/builtin -- "$bin" stream --stream test-vectors/builtin/expected.stream --profile a512
has "frame 2: DIFFERS"
has "GOLDEN MISMATCH: frame 2"
has "golden: 3 of 4 frames"

# the FX2's payload at high speed: every full WORDS packet is one 512-byte
# USB packet in a transfer of its own, ended by a zero-length one
usb 0 "FX2 payload" --payload 492 -- "$bin" stream --profile a256
has "payloads up to 492 bytes"
has "USB: high speed \(480 Mbit/s\), 512-byte bulk packets; 16 transfers of 65536 bytes in flight; [1-9][0-9]+ zero-length packets"
has "bulk OUT [0-9]+ bytes in [0-9]+ URBs \([1-9][0-9]+ zero-length packets\)"
# full speed: 64-byte packets, the ZLP rule from wMaxPacketSize, not 512:
# 640-byte protocol packets (a 620-byte payload) are whole packets there
usb 0 "full speed" --speed full --payload 620 -- "$bin" stream --profile a256
has "the board is on a full-speed link \(12 Mbit/s, 64-byte packets\)"
has "USB: full speed \(12 Mbit/s\), 64-byte bulk packets"
has "full speed, 64-byte packets; bulk OUT [0-9]+ bytes in [0-9]+ URBs \([1-9][0-9]+ zero-length packets\)"
# the transport's own transfers, filled to the buffer (a client writing
# without flushing, here usb_bench): 4 KiB of 64-byte packets, each ended
# by a ZLP, 1 MB intact through the board's core
usb 0 "whole-buffer transfers" --sink --speed full -- "$build/tests/usb_bench" --transfers 4 --buffer 4096 --mb 1
has "^4,4096,16384,1\.0,"
has "full speed, 64-byte packets; bulk OUT 10[0-9]{5} bytes in 2[0-9]{2} URBs \(2[0-9]{2} zero-length packets\)"
# 8-byte bulk packets (legal at full speed): every 40-byte RESULT is whole
# packets, ended by a zero-length one from the board, and so are many of the
# host's transfers
usb 0 "8-byte packets" --speed full --mps 8 -- "$bin" stream --profile a256
has "IN [0-9]+ bytes in [0-9]+ URBs \(0 short, [1-9][0-9]* zero-length"
has "8-byte bulk packets"
# a board that forgets the ZLP: the IN transfer ends by its timeout, with the
# RESULT in it (a timed-out transfer's data are kept)
usb 0 "no ZLP from the board" --speed full --mps 8 --no-zlp -- "$bin" stream --profile a256
has "[1-9][0-9]* IN transfers? ended by timeout with data"
has "hardware agrees"
# and one that sends empty packets between its replies
usb 0 "spurious ZLPs" --in-zlp -- "$bin" stream --profile a256
has "[1-9][0-9]* zero-length, 0 cut off"

# a stalled endpoint, mid-transfer: the rest of the transfers cancelled last
# first, the halt cleared once all are back, each resent from where it
# stopped, in order (the board's counters: nothing repeated, nothing lost)
usb 0 "OUT stall" --stall-out 3000 -- "$bin" stream --profile a256
has "1 stall recovered; [1-9][0-9]* bytes resent"
usb 0 "OUT stall, 16 small transfers in flight" --stall-out 5000 -- "$bin" stream --profile a256 --usb-buffer 1024
has "1 stall recovered"
usb 0 "IN stall" --stall-in 100 -- "$bin" stream --profile a256 --usb-buffer 1024
has "1 stall recovered"
has "; 1 halts cleared,"
# usbfs without NO_PACKET_SIZE_LIM: libusb splits each transfer into 16 KiB
# URBs with BULK_CONTINUATION; a stall in the middle of one
usb 0 "split transfers, a stall" --old-caps --stall-out 20000 -- "$bin" stream --profile a256 --usb-buffer 40000
has "1 stall recovered"
# a board that NAKs for longer than --timeout after taking part of a
# transfer: cancelled with part of its data sent, the rest sent again
usb 0 "NAK past the timeout" --nak-after 5000:600 -- "$bin" stream --profile a256 --usb-buffer 1536 --timeout 400
has "[1-9] OUT timeouts?; [1-9][0-9]* bytes resent"
has "hardware agrees"
# one that never takes data again: the link fails
usb 3 "NAK for good" --nak-after 5000:0 -- "$bin" stream --profile a256 --timeout 300
has "the board stopped answering|took no data"

# Ctrl-C while every transfer waits on a NAKing board: all cancelled and
# their callbacks run before the interface is released (no VIOLATION)
usb 130 "Ctrl-C" --nak-after 5000:0 --sigint 100 -- "$bin" stream --profile a256 --usb-buffer 1024
has "stream: interrupted: 0 of 4 frames confirmed"
has "[1-9][0-9]* discards"
# the board answers into an IN transfer just as the host cancels them at
# the end: nothing is resubmitted, nothing freed in flight
usb 0 "a reply during the teardown" --close-race -- "$bin" stream --profile a256
has "answering into an IN URB as the host cancels"
# cancelled transfers that never come back: after twice --timeout the host
# leaves them (and the handle) allocated rather than free memory the kernel
# may still write, and exits normally; the board sees them still in flight
usb 0 "!cancelled transfers that never come back" --stuck-close -- "$bin" stream --profile a256 --timeout 500
has "keeping the host's cancelled URBs for good"
has "hardware agrees"
has "VIOLATION: the device closed with 4 URBs in flight"
hasnt "Assertion|Sanitizer|runtime error"

# the device vanishes mid-transfer (ENODEV) and comes back as a new device:
# the stream starts over and every frame still matches the golden vector
usb 0 "unplugged and back" --unplug-after 20000:300 --profile a512 --golden test-vectors/builtin -- \
    "$bin" stream --stream test-vectors/builtin/expected.stream --profile a512
has "the board disconnected 1 time and came back"
has "plugged in 2 times"
has "golden: 4 of 4 frames"
usb 3 "unplugged for good" --unplug-after 20000:-1 -- "$bin" stream --profile a256 --wait 300
has "did not come back"
hasnt "came back;"

# permissions: udev applies the ACL a moment after the device appears
usb 0 "ACL 0.5 s late" --acl-delay 500 -- "$bin" stream --profile a256 --wait 0
has "hardware agrees"
usb 0 "ACL 0.5 s late, HID only" --acl-delay 500 -- "$bin" board info
has "albatros-sim: "
usb 3 "no ACL" --acl-delay never -- "$bin" stream --profile a256 --wait 0
has "LIBUSB_ERROR_ACCESS .*firmware/udev/70-albatros.rules"
((elapsed >= 2)) && ok || bad "no ACL: gave up after $elapsed s, not after retrying for 2 s"
# the hidraw node comes 0.7 s after the USB device: waited for
usb 0 "hidraw late" --hid-delay 700 -- "$bin" stream --profile a256
has "hardware agrees"
# HID reports shorter than asked for are errors, not zeros
usb 1 "short HID report" --hid-short 10 -- "$bin" board info
has "HID GET_REPORT 1: the board sent 10 of the report's 64 bytes"
usb 0 "short INFO, stream" --hid-short 10 -- "$bin" stream --profile a256
has "INFO report .*could not be read .*10 of the report's 64 bytes"
has "payloads up to 492 bytes"
# hidraw works both ways, and without a hidraw node (no usbhid) the same
# reports go as class requests on endpoint 0
usb 0 "board info over hidraw" -- "$bin" board info --json
has '"name": "albatros-sim", .*"max_payload": 16384'
usb 0 "board reset over hidraw" -- "$bin" board reset
has "^board reset"
usb 0 "no hidraw node" --hid none -- "$bin" stream --profile a256
has "HID through libusb \(no hidraw node\)"
usb 0 "no hidraw node, board info" --hid none -- "$bin" board info
has "albatros-sim: "
usb 0 "board list with its serial" -- "$bin" board list
has "^usb:001:002  1209:0001  serial 00000001"
# frames mode through libusb as well
usb 0 "frames mode" -- "$bin" stream --frames --profile a256
has "4 of 4 frames shown"
usb 0 "JSON report" -- "$bin" stream --profile a256 --json
has '"usb": \{"speed": "high", "speed_mbps": 480, "out_packet": 512, "in_packet": 512, "out_transfers": 16, "out_bytes": 65536'

# ---- the board's checks fire on a host that breaks them ----
usb 0 "!a transfer of whole packets without a ZLP" -- "$rogue" zlp
has "VIOLATION: the last bulk OUT transfer \(512 bytes"
usb 0 "!closed with a transfer in flight" -- "$rogue" leak
has "VIOLATION: the data interface released with 1 URBs in flight"
has "VIOLATION: the device closed with 1 URBs in flight"
usb 0 "!halt cleared in the callback" --stall-out 100 -- "$rogue" halt
has "VIOLATION: CLEAR_FEATURE\(HALT\) on endpoint 0x02 with 1 URBs still queued"

echo "$pass passed, $fail failed"
[[ $fail -eq 0 ]]
