#!/usr/bin/env python3
"""make-png-seeds.py — write the small PNG seeds of fuzz/corpus/png: every
colour type and bit depth libpng's simplified reader converts, interlacing,
and the shapes scene_texture_png rejects.  Standard library only; the files
are committed, this records how they were made."""
import struct
import sys
import zlib

ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2),
         (0, 1, 1, 2)]


def chunk(kind, data, crc=None):
    c = zlib.crc32(kind + data) & 0xFFFFFFFF if crc is None else crc
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", c)


def pack_row(samples, depth):
    """samples: ints already in the sample depth; packed big-endian."""
    if depth == 16:
        return b"".join(struct.pack(">H", s) for s in samples)
    if depth == 8:
        return bytes(samples)
    out, acc, bits = bytearray(), 0, 0
    for s in samples:
        acc = acc << depth | s
        bits += depth
        if bits == 8:
            out.append(acc)
            acc = bits = 0
    if bits:
        out.append(acc << (8 - bits))
    return bytes(out)


def png(w, h, ctype, depth, pixel, interlace=False, extra=b""):
    """pixel(x, y) -> tuple of samples for the colour type."""
    rows = []
    if interlace:
        for x0, y0, dx, dy in ADAM7:
            for y in range(y0, h, dy):
                xs = range(x0, w, dx)
                if xs:
                    rows.append(b"\0" + pack_row([s for x in xs for s in pixel(x, y)], depth))
    else:
        for y in range(h):
            rows.append(b"\0" + pack_row([s for x in range(w) for s in pixel(x, y)], depth))
    ihdr = struct.pack(">IIBBBBB", w, h, depth, ctype, 0, 0, 1 if interlace else 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + extra +
            chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b""))


def main(out):
    seeds = {
        "rgb8-2x2.png": png(2, 2, 2, 8, lambda x, y: (255 * x, 255 * y, 128)),
        "rgb8-16x16.png": png(16, 16, 2, 8, lambda x, y: (16 * x, 16 * y, (x ^ y) * 16)),
        "gray8-4x4.png": png(4, 4, 0, 8, lambda x, y: (x * 60 + y,)),
        "gray1-16x16.png": png(16, 16, 0, 1, lambda x, y: ((x + y) & 1,)),
        "gray-alpha16-4x4.png": png(4, 4, 4, 16, lambda x, y: (x * 9000, y * 20000)),
        "rgba8-interlaced-8x8.png": png(8, 8, 6, 8, lambda x, y: (x * 32, y * 32, 99, 255 - x),
                                        interlace=True),
        "rgb16-2x2.png": png(2, 2, 2, 16, lambda x, y: (65535 * x, 300, 65535 * y)),
        "palette4-8x8-trns.png": png(8, 8, 3, 4, lambda x, y: ((x + y) % 3,),
                                     extra=chunk(b"PLTE", bytes([255, 0, 0, 0, 255, 0, 0, 0, 255]))
                                     + chunk(b"tRNS", bytes([255, 128]))),
        "rejected-3x3.png": png(3, 3, 2, 8, lambda x, y: (x, y, 0)),
        "rejected-4x2.png": png(4, 2, 2, 8, lambda x, y: (x, y, 0)),
        "rejected-2048x2048.png": png(2048, 2048, 0, 1, lambda x, y: (0,)),
    }
    whole = png(8, 8, 2, 8, lambda x, y: (x * 30, y * 30, 7))
    seeds["truncated-idat.png"] = whole[:len(whole) - 20]
    bad = bytearray(png(4, 4, 2, 8, lambda x, y: (1, 2, 3)))
    bad[29] ^= 0xFF   # IHDR's CRC
    seeds["bad-ihdr-crc.png"] = bytes(bad)
    for name, data in seeds.items():
        with open(f"{out}/{name}", "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "fuzz/corpus/png")
