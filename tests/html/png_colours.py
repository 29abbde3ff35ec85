#!/usr/bin/env python3
"""Prints what a PNG screenshot shows, for the HTML page tests: its size, the
share of pixels that differ from the most common colour (the background),
and the number of distinct colours, over the whole image and inside a box.

    png_colours.py FILE [X0 Y0 X1 Y1]

Prints "width height changed_share colours box_changed_share box_colours".
Reads 8-bit RGB and RGBA PNGs without interlacing (what Chromium writes),
with zlib only."""
import struct
import sys
import zlib


def decode(path):
    data = open(path, 'rb').read()
    if data[:8] != b'\x89PNG\r\n\x1a\n':
        raise SystemExit(path + ': not a PNG')
    at, idat, header = 8, [], None
    while at < len(data):
        length, kind = struct.unpack('>I4s', data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b'IHDR':
            header = struct.unpack('>IIBBBBB', body)
        elif kind == b'IDAT':
            idat.append(body)
        at += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        raise SystemExit(path + ': unsupported PNG (depth %d, colour type %d)' % (depth, colour))
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(b''.join(idat))
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        kind, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        if kind == 1:
            for i in range(channels, stride):
                line[i] = (line[i] + line[i - channels]) & 255
        elif kind == 2:
            line = bytearray((a + b) & 255 for a, b in zip(line, previous))
        elif kind == 3:
            for i in range(stride):
                left = line[i - channels] if i >= channels else 0
                line[i] = (line[i] + ((left + previous[i]) >> 1)) & 255
        elif kind == 4:
            for i in range(stride):
                a = line[i - channels] if i >= channels else 0
                b = previous[i]
                c = previous[i - channels] if i >= channels else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else (b if pb <= pc else c))) & 255
        rows.append(bytes(line))
        previous = line
    return width, height, channels, rows


def summary(width, channels, rows, x0, y0, x1, y1):
    counts = {}
    for row in rows[max(0, y0):y1]:
        for x in range(max(0, x0), min(x1, width)):
            pixel = row[x * channels:x * channels + 3]
            counts[pixel] = counts.get(pixel, 0) + 1
    total = sum(counts.values())
    if not total:
        return 0.0, 0
    return 1 - max(counts.values()) / total, len(counts)


def main():
    width, height, channels, rows = decode(sys.argv[1])
    box = [int(v) for v in sys.argv[2:6]] if len(sys.argv) >= 6 else [0, 0, width, height]
    whole = summary(width, channels, rows, 0, 0, width, height)
    inside = summary(width, channels, rows, box[0], box[1], box[2], box[3])
    print(width, height, '%.4f' % whole[0], whole[1], '%.4f' % inside[0], inside[1])


main()
