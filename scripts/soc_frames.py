#!/usr/bin/env python3
"""The camera's input for the SoC co-simulation (scripts/soc.sh): a `coopwin scene` folder's
first N frames (8-bit gray PNG, 256x256) as raw rows, RAW/frameKKKK.raw, and the target on
the first frame (groundtruth.csv's first centre, rounded to whole pixels) printed as X,Y.
Standard library only: PNG's zlib stream and its five row filters.

    scripts/soc_frames.py SCENE RAW N
"""
import csv
import struct
import sys
import zlib


def gray_png(path):
    """The rows of an 8-bit gray, non-interlaced PNG, as (width, height, bytes)."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"soc_frames: {path} is not a PNG")
    pos, idat, head = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
    w, h, depth, colour, _, _, interlace = head
    if (depth, colour, interlace) != (8, 0, 0):
        sys.exit(f"soc_frames: {path}: not 8-bit gray non-interlaced (depth {depth}, colour type {colour})")
    raw, out, prev = zlib.decompress(idat), bytearray(), bytearray(w)
    for y in range(h):
        f, line = raw[y * (w + 1)], bytearray(raw[y * (w + 1) + 1:(y + 1) * (w + 1)])
        for x in range(w):
            a = line[x - 1] if x else 0
            b, c = prev[x], (prev[x - 1] if x else 0)
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
            elif f != 0:
                sys.exit(f"soc_frames: {path}: unknown row filter {f}")
        out += line
        prev = line
    return w, h, bytes(out)


def main():
    scene, raw, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
    for k in range(n):
        w, h, px = gray_png(f"{scene}/frame_{k:05d}.png")
        if (w, h) != (256, 256):
            sys.exit(f"soc_frames: {scene}/frame_{k:05d}.png is {w}x{h}, the SoC's camera is 256x256")
        open(f"{raw}/frame{k:04d}.raw", "wb").write(px)
    row = next(csv.DictReader(open(f"{scene}/groundtruth.csv")))
    print(f"{round(float(row['centre_x']))},{round(float(row['centre_y']))}")


if __name__ == "__main__":
    main()
