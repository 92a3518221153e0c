#!/usr/bin/env python3
"""make-bridge-seeds.py — seed inputs for the bridge's harnesses: fuzz_fw
(what a host sends the firmware) and fuzz_link (what a board sends the host).
Each seed is one byte that seeds the harness's cuts, then packets framed as
docs/usb-protocol.md says: 'ALB1', type, flags, two zero bytes, u32 seq,
u32 length, payload, CRC-32 (zlib's) of header and payload, little-endian.
Run from the repository's root: python3 fuzz/make-bridge-seeds.py"""
import struct
import zlib

def packet(ptype, seq, payload=b"", flags=0):
    head = b"ALB1" + struct.pack("<BBHII", ptype, flags, 0, seq, len(payload))
    return head + payload + struct.pack("<I", zlib.crc32(head + payload))

def u32(*v):
    return struct.pack("<%dI" % len(v), *v)

# real word-stream words: a t32 stream of the stream harness's seeds, cut
# after CONFIG (3 words) and into its frame
STREAM = open("fuzz/corpus/stream/t32-screenspace.stream", "rb").read()
CONFIG = STREAM[:12]
FRAME = STREAM[12:-8]
FRAME_END = STREAM[-8:-4]

def seq_of(*pkts):
    out, seq = b"", 0
    for t, p in pkts:
        out += packet(t, seq, p)
        seq += 1
    return out

host = {
    "reset-words-ping": seq_of((0x01, b""), (0x02, CONFIG + FRAME + FRAME_END), (0x06, b"")),
    "resume-query-readback": seq_of((0x01, b""), (0x02, CONFIG), (0x03, u32(1)), (0x04, u32(0)),
                                    (0x07, u32(2)), (0x07, u32(99))),
    "gap-then-resume": packet(0x01, 0) + packet(0x02, 5, FRAME) + packet(0x03, 6, u32(0)),
    "corrupt-crc": packet(0x01, 0)[:-1] + b"\x00" + packet(0x06, 1),
    "garbage-between": b"xxALB" + packet(0x01, 0) + b"\xff" * 7 + packet(0x06, 1),
    "tile": seq_of((0x01, b""), (0x05, struct.pack("<IHHHH", 0, 1, 2, 2, 1) + b"\x10\x20\x30" * 2)),
    "odd-words": seq_of((0x01, b""), (0x02, b"\x01\x02\x03")),
    "huge-length": b"ALB1" + struct.pack("<BBHII", 2, 0, 0, 0, 0xFFFFFFF0),
    "duplicate": packet(0x01, 0) + packet(0x06, 1) + packet(0x06, 1),
    "unknown-type": seq_of((0x01, b""), (0x7F, b"abc"), (0x81, u32(0, 0, 0, 0, 0))),
}
board = {
    "results-match": seq_of((0x81, u32(0, 0x11111111, 0, 0, 0)), (0x81, u32(1, 0x22222222, 100, 0, 0)),
                            (0x81, u32(2, 0x33333333, 200, 0, 0)), (0x82, u32(*range(9)))),
    "result-mismatch-then-pixels": seq_of((0x81, u32(0, 0xDEAD, 0, 0, 0)),
                                          (0x81, u32(1, 0x22222222, 100, 0, 0)),
                                          (0x81, u32(2, 0x33333333, 200, 0, 0)),
                                          (0x84, u32(0, 0, 16) + b"\x01\x00" * 48)),
    "error-then-results": seq_of((0x83, u32(2, 3, 2, 0)), (0x81, u32(0, 0x11111111, 0, 0, 0)),
                                 (0x83, u32(1, 5, 5, 0)), (0x81, u32(1, 0x22222222, 100, 0, 0)),
                                 (0x81, u32(2, 0x33333333, 200, 0, 0))),
    "unknown-frame": seq_of((0x81, u32(77, 0, 0, 0, 0))),
    "short-payloads": seq_of((0x81, u32(0)), (0x83, b""), (0x84, u32(0, 15, 2))),
    "pixels-bad-count": seq_of((0x81, u32(0, 1, 0, 0, 0)), (0x84, u32(0, 0, 0xFFFFFFFF))),
    "garbage-and-gaps": b"\x00ALB" + packet(0x81, 4, u32(0, 0x11111111, 0, 0, 0)) + b"ALB1ALB1"
                        + packet(0x81, 2, u32(1, 0x22222222, 100, 0, 0)),
}
for folder, seeds in (("fw", host), ("link", board)):
    for i, (name, data) in enumerate(sorted(seeds.items())):
        with open("fuzz/corpus/%s/%s.bin" % (folder, name), "wb") as f:
            f.write(bytes([i * 37 % 256]) + data)
