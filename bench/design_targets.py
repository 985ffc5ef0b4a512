#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writes the designer's benchmark targets as 16-bit PGM files (no
dependencies beyond Python): a logo on black (a ring, a five-pointed star
and a bar, anti-aliased by 4x4 supersampling) and, given a silhouette PNG
(8-bit grey/RGB/RGBA, non-interlaced), its inverse: light figure on black."""
import math
import struct
import sys
import zlib


def write_pgm(path, width, height, values):
    with open(path, "wb") as f:
        f.write(b"P5\n%d %d\n65535\n" % (width, height))
        f.write(b"".join(struct.pack(">H", max(0, min(65535, round(v * 65535)))) for v in values))


def logo(n):
    def inside(x, y):  # x, y in [-1, 1]
        r = math.hypot(x, y)
        if 0.78 < r < 0.9:
            return True
        a = math.atan2(y, x) + math.pi / 2
        k = (a % (2 * math.pi / 5)) - math.pi / 5
        star = 0.3 + 0.32 * (1 - abs(k) / (math.pi / 5)) ** 2
        if r < star and y > -0.45:
            return True
        return abs(x) < 0.5 and -0.68 < y < -0.56
    out = []
    for row in range(n):
        for col in range(n):
            hits = sum(inside((col + (sx + 0.5) / 4) / n * 2 - 1, 1 - (row + (sy + 0.5) / 4) / n * 2)
                       for sx in range(4) for sy in range(4))
            out.append(hits / 16)
    return out


def read_png_grey(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", "not a PNG"
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and interlace == 0, "8-bit non-interlaced only"
            channels = {0: 1, 2: 3, 4: 2, 6: 4}[ctype]
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride, prev, rows = zlib.decompress(idat), width * channels, bytearray(width * channels), []
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            p = {0: 0, 1: a, 2: b, 3: (a + b) // 2}.get(f)
            if f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            line[i] = (line[i] + p) & 255
        rows.append(line)
        prev = line
    grey = [rows[y][x * channels] / 255 for y in range(height) for x in range(width)]
    return width, height, grey


if __name__ == "__main__":
    out = sys.argv[1]
    write_pgm(out + "/logo.pgm", 512, 512, logo(512))
    if len(sys.argv) > 2:
        w, h, grey = read_png_grey(sys.argv[2])
        write_pgm(out + "/silhouette.pgm", w, h, [1 - g for g in grey])
