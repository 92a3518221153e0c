#!/usr/bin/env python3
"""make-streams.py — write the malformed word streams of this folder from
one valid t32 stream (CONFIG, FRAME, two 5-edge FACEs, FRAME_END, END: the
words are listed below), each with one defect.  Run from this folder; the
files are committed, this records how they were made."""
import struct

BASE = [
    0xa5010002, 0x0000180a, 0x3f800000,                          # CONFIG F=10, 24-bit, near 1
    0xf0000000, 0, 0, 0, 0,                                      # FRAME 0
    0xfa050000, 0, 0x00ff0000, 0xffffffe9, 0, 0, 0x00400000,     # FACE 0: header, depth
    0x00000876, 0x00000914, 0xc0000f76, 0x00000bc5, 0x80000840, 0x00000c40,
    0x00000880, 0x00000880, 0x40000f80, 0x00000f80,
    0xfa050000, 1, 0x0000ff00, 0xffffffe9, 0xfffe07e0, 0x00400000, 0x004e85e8,  # FACE 1
    0x80000900, 0x00000900, 0x0000088a, 0x00000c3b, 0x40000f76, 0x00000bc5,
    0x80000900, 0x00000900, 0xc0000f80, 0x00000f80,
    0xfe000002,                                                  # FRAME_END 2
    0xff000000,                                                  # END
]
FACE0 = 8    # word index of the first FACE header


def write(name, words, raw=None):
    with open(name, "wb") as f:
        f.write(raw if raw is not None else struct.pack("<%dI" % len(words), *words))


def patched(**at):
    w = list(BASE)
    for k, v in at.items():
        w[int(k[1:])] = v
    return w


def main():
    write("stream-valid-t32.stream", BASE)
    write("stream-empty.stream", [], b"")
    write("stream-odd-length.stream", [], struct.pack("<2I", *BASE[:2])[:6])
    write("stream-bad-header.stream", patched(w0=0x12000000))
    write("stream-config-version.stream", patched(w0=0xa5020002))
    write("stream-config-length.stream", patched(w0=0xa5010003))
    write("stream-config-near-nan.stream", patched(w2=0x7fc00000))
    write("stream-config-formats.stream", patched(w1=0x00001803))
    write("stream-frame-before-config.stream", BASE[3:])
    write("stream-second-config.stream", BASE[:3] + BASE)
    write("stream-unknown-packet.stream", BASE[:3] + [0x12345678] + BASE[3:])
    write("stream-face-outside-frame.stream", BASE[:3] + BASE[FACE0:FACE0 + 17] + BASE[-1:])
    write("stream-truncated-in-face.stream", BASE[:FACE0 + 10])
    write("stream-no-end.stream", BASE[:-1])
    write("stream-words-after-end.stream", BASE + [0, 0])
    write("stream-frame-end-count.stream", patched(w42=0xfe000003))
    write("stream-face-65-edges.stream", patched(w8=0xfa410000))
    write("stream-face-flags.stream", patched(w8=0xfa050800))
    write("stream-exp-range.stream", patched(w11=200))
    write("stream-mantissa-range.stream", patched(w14=0x01000000))
    write("stream-edge-range.stream", patched(w15=0x00003fff))
    write("stream-fog-far-not-beyond-near.stream", patched(w5=0x80000000, w6=0x100, w7=0x100))
    write("stream-face-colour-high-bits.stream", patched(w10=0x01ff0000))
    write("stream-end-reserved-bits.stream", patched(w43=0xff000001))
    write("stream-texture-too-big.stream", BASE[:3] + [0xa7000b00] + BASE[3:])
    write("stream-texture-reserved-bits.stream", BASE[:3] + [0xa7000101] + BASE[3:])
    # a FACE with the T flag: u and v forms after depth, and no TEXTURE packet
    face_t = [0xfa050200] + BASE[FACE0 + 1:FACE0 + 7] + [0, 0, 0, 0] * 2 + BASE[FACE0 + 7:FACE0 + 17]
    write("stream-texture-not-loaded.stream", BASE[:FACE0] + face_t + [0xfe000001, 0xff000000])


if __name__ == "__main__":
    main()
