#!/usr/bin/env python3
"""Crops the same rectangle out of several 8-bit RGB(A) PNGs, enlarges it by an integer factor
(nearest neighbour) and puts the crops side by side in one PNG. Standard library only; used to
make the pictures in docs/img from iaa's own outputs.

  tools/doc_crops.py X0 Y0 X1 Y1 SCALE OUT.png IN1.png IN2.png ...
"""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        sys.exit(f'doc_crops: {path} is not a PNG file')
    pos, idat, width, height, channels = 8, b'', 0, 0, 0
    while pos < len(data):
        (n,) = struct.unpack('>I', data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b'IHDR':
            width, height, depth, colour = struct.unpack('>IIBB', body[:10])
            if depth != 8 or colour not in (2, 6) or body[12] != 0:
                sys.exit(f'doc_crops: {path}: only 8-bit RGB or RGBA, not interlaced')
            channels = 3 if colour == 2 else 4
        elif kind == b'IDAT':
            idat += body
    raw, stride, rows, prev, p = zlib.decompress(idat), width * channels, [], None, 0
    prev = bytearray(stride)
    for _ in range(height):
        kind, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + ((a + b) >> 1)) & 255
            elif kind == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else (b if pb <= pc else c))) & 255
        rows.append(line)
        prev = line
    return width, height, channels, rows


def write_png(path, rows):
    height, width = len(rows), len(rows[0]) // 3

    def chunk(kind, body):
        return struct.pack('>I', len(body)) + kind + body + struct.pack(
            '>I', zlib.crc32(kind + body) & 0xffffffff)

    raw = b''.join(b'\x00' + r for r in rows)
    header = struct.pack('>IIBBBBB', width, height, 8, 2, 0, 0, 0)
    png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', header) + chunk(b'IDAT', zlib.compress(raw, 9))
    open(path, 'wb').write(png + chunk(b'IEND', b''))


def main():
    if len(sys.argv) < 8:
        sys.exit(__doc__)
    x0, y0, x1, y1, k = (int(v) for v in sys.argv[1:6])
    crops = []
    for path in sys.argv[7:]:
        w, h, ch, rows = read_png(path)
        if not (0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h and k >= 1):
            sys.exit(f'doc_crops: the rectangle must lie in the {w}x{h} image and SCALE be >= 1')
        out = []
        for y in range(y0, y1):
            line = b''.join(bytes(rows[y][x * ch:x * ch + 3]) * k for x in range(x0, x1))
            out.extend([line] * k)
        crops.append(out)
    gap = b'\xff\xff\xff' * 6
    write_png(sys.argv[6], [gap.join(c[i] for c in crops) for i in range(len(crops[0]))])


if __name__ == '__main__':
    main()
