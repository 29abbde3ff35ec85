#!/usr/bin/env python3
"""Writes a long synthetic cache for the report benchmarks: a square sheet
(N x N vertices) whose travelling wave crosses a static floor grid, so that
every frame has intersections along the wave's zero lines and every step has
collisions where vertices cross the floor; the problems move slowly, so that
they persist as tracks.

    make_long_cache.py DIR FRAMES [N]

writes DIR/sheet.obj + DIR/sheet.pc2 (the moving sheet) and DIR/floor.obj +
DIR/floor.pc2 (the floor, still). Pure Python (struct), no dependencies.
"""
import math
import os
import struct
import sys


def grid(n, size, z):
    vertices = [(size * i / (n - 1), size * j / (n - 1), z) for j in range(n) for i in range(n)]
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces.append((a, a + 1, a + n + 1))
            faces.append((a, a + n + 1, a + n))
    return vertices, faces


def write_obj(path, name, vertices, faces):
    with open(path, "w") as out:
        out.write(f"o {name}\n")
        out.writelines(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in vertices)
        out.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)


def write_pc2(path, frames):
    with open(path, "wb") as out:
        out.write(struct.pack("<12sii f f i", b"POINTCACHE2\0", 1, len(frames[0]), 0.0, 1.0, len(frames)))
        for positions in frames:
            out.write(b"".join(struct.pack("<3f", *p) for p in positions))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    directory, frame_count = sys.argv[1], int(sys.argv[2])
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 100
    os.makedirs(directory, exist_ok=True)
    sheet, sheet_faces = grid(n, 1.0, 0.0)
    floor, floor_faces = grid(21, 1.2, 0.0)
    floor = [(x - 0.1, y - 0.1, z) for x, y, z in floor]
    write_obj(os.path.join(directory, "sheet.obj"), "sheet", sheet, sheet_faces)
    write_obj(os.path.join(directory, "floor.obj"), "floor", floor, floor_faces)
    amplitude, wavelength, speed = 0.05, 0.5, 0.002  # the wave moves 1/5 of a sheet cell per frame at N = 100
    frames = []
    for f in range(frame_count):
        shift = speed * f
        frames.append([(x, y, 0.01 + amplitude * math.sin(2 * math.pi * (x - shift) / wavelength)) for x, y, _ in sheet])
    write_pc2(os.path.join(directory, "sheet.pc2"), frames)
    write_pc2(os.path.join(directory, "floor.pc2"), [floor] * frame_count)


if __name__ == "__main__":
    main()
