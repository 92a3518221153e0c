#!/usr/bin/env bash
# cli-stream.sh ALBATROS — `albatros stream` and `albatros board` through the
# simulated board: a board that takes 492-byte payloads (the FX2's), link
# faults named in the report, text and JSON agreeing on every count, Ctrl-C
# with its partial report, and the JSON of `board`.
source "$(dirname "$0")/lib.sh"

# a scene of many frames: the simulated board re-runs the stream for every
# frame, so streaming it takes ~20 s (far longer under valgrind) unless stopped
gem='albatros-scene 1
near 0.5
light 0.5 0.7 -0.6 ambient 0.25
observer at 0 0 -12 fov 50
object gem moving yaw 10
 v 2 0 0 n 1 0 0
 v -2 0 0 n -1 0 0
 v 0 3 0 n 0 1 0
 v 0 -3 0 n 0 -1 0
 v 0 0 2 n 0 0 1
 v 0 0 -2 n 0 0 -1
 colour 230 140 40
 f 5 3 1
 f 2 3 5
 f 6 3 2
 f 1 3 6
 f 1 4 5
 f 5 4 2
 f 2 4 6
 f 6 4 1
end'
{ echo "$gem"; for ((i = 1; i <= 150; i++)); do printf 'frame\n pose gem yaw %d\n' $((7 * i)); done; } > "$tmp/long.scene"
# the signal tests' stream: long enough (about a second and a half to send)
# that a signal sent once it has begun cannot miss it on a loaded machine
{ echo "$gem"; for ((i = 1; i <= 1500; i++)); do printf 'frame\n pose gem yaw %d\n' $((7 * i)); done; } > "$tmp/longer.scene"
{ echo "$gem"; for ((i = 1; i <= 40; i++)); do printf 'frame\n pose gem yaw %d\n' $((9 * i)); done; } > "$tmp/forty.scene"

# the board's payload comes from its INFO report: a board that takes 492
# bytes (one USB packet, as the FX2 firmware) gets WORDS and TILEs that fit
expect 0 "albatros-sim: .*payloads up to 492 bytes" "$bin" board info --sim --sim-payload 492
expect 0 "4 of 4 frames match the emulator .*packets \(payloads up to 492 bytes\)" \
    "$bin" stream --sim --sim-payload 492 --profile a256
expect 0 '"max_payload": 492, "board_errors": 0' "$bin" stream --sim --sim-payload 492 --profile a256 --json
expect 0 "4 of 4 frames shown; [0-9]+ packets \(payloads up to 492 bytes\)" \
    "$bin" stream --sim --frames --sim-payload 492 --profile a256
expect 0 '"max_payload": 492, .*"display": "identical"|"display": "identical".*"max_payload": 492' \
    "$bin" stream --sim --frames --sim-payload 492 --profile a256 --json
expect 0 "payloads up to 16384 bytes" "$bin" stream --sim --profile a256
expect 2 "expected a number up to 16384" "$bin" stream --sim --sim-payload 20000
# more frames than the window of 16 ahead of the last RESULT: the window slides
expect 0 "40 of 40 frames match the emulator" "$bin" stream --sim --profile t32 "$tmp/forty.scene"

# every ERROR code counted, the same in text and JSON: a corrupted RESET
# leaves the board unsynchronised, so it refuses the next packets (MODE)
expect 0 "board reported 3 errors \(wrong mode 3\)" "$bin" stream --sim --profile t32 --fault corrupt=3
expect 0 '"board_errors": 3, "board_error_codes": \{"bad_crc": 0, "seq_gap": 0, "duplicate": 0, "bad_type": 0, "bad_length": 0, "stream": 0, "mode": 3, "overflow": 0, "unknown": 0\}' \
    "$bin" stream --sim --profile t32 --fault corrupt=3 --json
expect 0 '"first_link_error": "board: wrong mode at packet 1 \(WORDS: words 0\.\.' \
    "$bin" stream --sim --profile t32 --fault corrupt=3 --json
# the host's own decoder counts the board's corrupted bytes, in both forms
expect 0 "host saw 1 bad CRCs, [1-9][0-9]* garbage bytes" "$bin" stream --sim --profile a256 --fault corrupt-reply=30
expect 0 '"host_crc_errors": 1, "host_garbage_bytes": [1-9]' "$bin" stream --sim --profile a256 --fault corrupt-reply=30 --json

# a lost packet is named: its sequence number, its words, its frame
expect 0 "first link error: board: sequence gap: packet 5 \(WORDS: words [0-9]+\.\.[0-9]+, frame 2\) never arrived" \
    "$bin" stream --sim --profile a256 --fault drop=6
# a packet cut short: a bad CRC where it lay, then the gap; the stream recovers
expect 0 "board reported 2 errors \(bad CRC 1, sequence gap 1\)" \
    "$bin" stream --sim --profile a256 --fault truncate=6
expect 0 "hardware agrees" "$bin" stream --sim --profile a256 --fault truncate=6
expect 0 "first link error: board: bad CRC at packet 39 \(TILE: frame 0, tile at \(0, 19\)\)" \
    "$bin" stream --sim --frames --profile a256 --sim-payload 492 --fault truncate=40
expect 0 '"resends": 1, "display": "identical"' \
    "$bin" stream --sim --frames --profile a256 --sim-payload 492 --fault truncate=40 --json
# the last packet of a frame cut short, nothing behind it: the QUERY goes
# behind zero bytes that complete it, the gap shows, the frame is resumed
printf 'albatros-scene 1\nobject t\n v -1 -1 4\n v 1 -1 4\n v 0 1 4\n f 1 2 3\nend\n' > "$tmp/tri.scene"
expect 0 "1 of 1 frames match .*1 resumes, 1 queries" "$bin" stream --sim --wait 0 "$tmp/tri.scene" --fault truncate=3
expect 0 "hardware agrees" "$bin" stream --sim --wait 0 "$tmp/tri.scene" --sim-payload 492 --fault truncate=3
expect 0 "4 of 4 frames match .*1 queries" "$bin" stream --sim --wait 0 --fault truncate=7
# the stream's END cut short: the closing PING goes again behind the padding
expect 0 "first link error: board: sequence gap: packet 3 \(WORDS: words 26\.\.26, the stream's end\) never arrived" \
    "$bin" stream --sim --wait 0 "$tmp/tri.scene" --fault truncate=4
# a silent board: the time the host waited, measured
expect 3 "the board stopped answering: no RESULT for frame [0-9]+ in [0-9]+\.[0-9]+ s after sending up to frame [0-9]+ and a QUERY \(each read waits up to 2000 ms\)" \
    "$bin" stream --sim --wait 0 --profile a256 --fault silence=30
expect 0 "truncate=N +send only the first half of the N-th packet" "$bin" stream --help
expect 0 "corrupt=N +flip a bit of the N-th byte sent" "$bin" stream --help

# Ctrl-C: stopped once the stream has begun (its first line, printed once
# the handler is in place), however slowly the emulator's run before it goes
"$bin" stream --sim --profile a256 "$tmp/longer.scene" > "$tmp/int.out" 2>&1 &
pid=$!
for ((i = 0; i < 6000; i++)); do grep -q '^stream: 1500 frames to send' "$tmp/int.out" && break; sleep 0.02; done
kill -INT $pid
wait $pid
rc=$?
[[ $rc -eq 130 ]] && grep -qE '^stream: interrupted: [0-9]+ of 1500 frames confirmed by the board$' "$tmp/int.out" &&
    grep -qE '^stream: [0-9]+ of 1500 frames match the emulator' "$tmp/int.out" &&
    ! grep -qE 'no result|DIFFERS' "$tmp/int.out" && ok || bad "SIGINT: exit $rc: $(cat "$tmp/int.out")"
n=$(sed -nE 's/^stream: interrupted: ([0-9]+) of 1500.*/\1/p' "$tmp/int.out")
[[ -n $n && $n -lt 1500 ]] && ok || bad "SIGINT: $n frames confirmed: not interrupted?"
# SIGTERM the same
"$bin" stream --sim --profile a256 "$tmp/longer.scene" > "$tmp/term.out" 2>&1 &
pid=$!
for ((i = 0; i < 6000; i++)); do grep -q '^stream: 1500 frames to send' "$tmp/term.out" && break; sleep 0.02; done
kill -TERM $pid
wait $pid
rc=$?
[[ $rc -eq 130 ]] && grep -qE '^stream: interrupted: [0-9]+ of 1500 frames confirmed' "$tmp/term.out" &&
    ok || bad "SIGTERM: exit $rc: $(cat "$tmp/term.out")"

# board: JSON where asked, the usage names --wait
expect 0 '^\{"boards": \[\{"id": "sim:0", "kind": "sim", "profile": "a256"\}\]\}$' "$bin" board list --sim --json --profile a256
expect 0 '^\{"reset": "link, VP and counters"\}$' "$bin" board reset --sim --json
expect 0 '"max_payload": 492\}$' "$bin" board info --sim --json --sim-payload 492
expect 0 "usage: albatros board .*--wait MS" "$bin" board --help
# the word-stream summary gives the rate, as frames mode does
expect 0 "stream: 4 of 4 frames match .* MB in [0-9.]+ s \([0-9.]+ MB/s\)" "$bin" stream --sim --profile t32

# exit status: 0 agree, 1 frames differ, 2 nothing sent (usage, an unreadable
# or malformed scene or stream, a stream made for another profile), 3 the
# link failed; 130 (interrupted) above
"$bin" gp --profile t32 -q -o "$tmp/t32.stream" || bad "gp --profile t32"
expect 0 "hardware agrees" "$bin" stream --sim --profile t32 --stream "$tmp/t32.stream"
expect 1 "frame 0: DIFFERS" "$bin" stream --sim --profile t32 --fault flip=0
expect 1 '"result": "differs"' "$bin" stream --sim --profile t32 --fault flip=0 --json
expect 2 "the stream's formats .* differ from the profile's" "$bin" stream --sim --stream "$tmp/t32.stream"
expect 2 "the word stream is malformed" \
    "$bin" stream --sim --stream "$(dirname "$0")/data/malformed/stream-unknown-packet.stream"
expect 2 "cannot open" "$bin" stream --sim --stream "$tmp/none.stream"
expect 2 "cannot open scene" "$bin" stream --sim "$tmp/none.scene"
expect 2 "unknown option '--bogus'" "$bin" stream --sim --bogus
expect 3 "the board stopped answering" "$bin" stream --sim --profile t32 --fault silence=1 --timeout 50
expect 3 '"result": "failed"' "$bin" stream --sim --profile t32 --fault silence=1 --timeout 50 --json
expect 3 "device disconnected" "$bin" stream --sim --profile t32 --fault disconnect=100 --wait 0
expect 3 "stopped answering" "$bin" stream --sim --frames --profile t32 --fault silence=1 --timeout 20
expect 0 "2 nothing was sent: a usage.*error, a scene or stream FILE unreadable or malformed, a stream made for.*another profile; 3 the link failed" \
    bash -c '"$0" stream --help | tr "\n" " "' "$bin"

# USB ids are hexadecimal, as lsusb and the default 1209:0001 show them, 0x
# or not (without a board on the bus; 1209 in decimal would be 04b9)
expect 0 "^no board 1209:0001 on the USB bus$" "$bin" board list --vid 1209
expect 0 "^no board 1209:0001 on the USB bus$" "$bin" board list --vid 0x1209 --pid 0X0001
expect 0 "^no board 04b9:00ff on the USB bus$" "$bin" board list --vid 04B9 --pid ff
expect 3 "opening USB device 1209:0001" "$bin" stream --profile t32 --vid 1209 --pid 1 --wait 0
expect 2 "--vid 12345: expected a hexadecimal USB id" "$bin" board list --vid 12345
expect 2 "--pid 0x: expected a hexadecimal USB id" "$bin" stream --sim --pid 0x
expect 2 "--vid -1: expected a hexadecimal USB id" "$bin" stream --sim --vid -1
expect 0 "USB ids in hexadecimal as lsusb shows them, 0x optional" "$bin" stream --help
expect 0 "USB ids in hexadecimal as lsusb shows them, 0x optional" "$bin" board --help

# a fault kind strikes as often as it is given; N counts from 1; silence,
# disconnect and flip happen once
expect 0 "board reported 2 errors \(sequence gap 2\)" "$bin" stream --sim --profile a256 --fault drop=3 --fault drop=8
expect 0 "host saw 2 bad CRCs" "$bin" stream --sim --profile a256 --fault corrupt-reply=30 --fault corrupt-reply=90
expect 2 "--fault drop=0: N counts from 1" "$bin" stream --sim --fault drop=0
expect 2 "--fault corrupt=0: N counts from 1" "$bin" stream --sim --fault corrupt=0
expect 1 "3 of 4 frames match" "$bin" stream --sim --profile t32 --fault flip=0   # a frame number, from 0
expect 2 "a second flip fault" "$bin" stream --sim --fault flip=1 --fault flip=2
expect 2 "a second silence fault" "$bin" stream --sim --fault silence=9 --fault silence=20
expect 2 "at most 8 faults of one kind" "$bin" stream --sim $(for i in 1 2 3 4 5 6 7 8 9; do echo --fault swap=$((4 * i)); done)
expect 0 "repeatable, up to.* 8 of a kind, but silence, disconnect and flip once only" \
    bash -c '"$0" stream --help | tr "\n" " "' "$bin"

# board list --wait: polls until a board is on the bus or the time is up;
# the simulated board is always there (a wait of 10 minutes would hit the
# timeout: no timing measured, only "did not wait")
expect 0 "^sim:0  simulated board" timeout 120 "$bin" board list --sim --wait 600000
ms() { date +%s%3N; }
t0=$(ms)
expect 0 "^no board 1209:0001 on the USB bus$" "$bin" board list --wait 700
(( $(ms) - t0 >= 700 )) && ok || bad "board list --wait 700 returned after $(( $(ms) - t0 )) ms"
expect 0 "list waits until one is on the bus \(--sim: at once\)" "$bin" board --help

# the simulated board runs the emulator's profile with every --set and --size
expect 0 "4 of 4 frames match" "$bin" stream --sim --profile t32 --set aa=1
expect 0 "hardware agrees" "$bin" stream --sim --profile t32 --size 64x64 --set depth_bits=16

finish
