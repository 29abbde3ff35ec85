#!/usr/bin/env python3
"""Writes the long synthetic cache of bench/report/make_long_cache.py (a
sheet whose travelling wave crosses a still floor) with numpy, fast enough for
a large cloth over hundreds of frames; same files, same scene, same values.

    mpi-make-cloth.py DIR FRAMES [N]
"""
import argparse
import os
import struct
import sys

import numpy as np

# make_long_cache.py lies beside this script in the bundle, in bench/report/ in the tree.
here = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [here, os.path.join(here, "..", "bench", "report")]
import make_long_cache as scene  # noqa: E402


def main():
    arguments = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    arguments.add_argument("directory")
    arguments.add_argument("frames", type=int)
    arguments.add_argument("n", type=int, nargs="?", default=100, help="sheet vertices per side")
    args = arguments.parse_args()
    frame_count = args.frames
    os.makedirs(args.directory, exist_ok=True)
    path = lambda name: os.path.join(args.directory, name)  # noqa: E731
    sheet, sheet_faces = scene.grid(args.n, 1.0, 0.0)
    floor_rest, floor_faces = scene.grid(21, 1.2, 0.0)
    floor = [(x - 0.1, y - 0.1, z) for x, y, z in floor_rest]
    scene.write_obj(path("sheet.obj"), "sheet", sheet, sheet_faces)
    scene.write_obj(path("floor.obj"), "floor", floor, floor_faces)
    amplitude, wavelength, speed = 0.05, 0.5, 0.002  # as make_long_cache.py
    rest = np.array(sheet, dtype=np.float64)
    with open(path("sheet.pc2"), "wb") as out:
        out.write(struct.pack("<12sii f f i", b"POINTCACHE2\0", 1, len(sheet), 0.0, 1.0, frame_count))
        frame = np.empty((len(sheet), 3), dtype=np.float32)
        frame[:, 0], frame[:, 1] = rest[:, 0], rest[:, 1]
        for f in range(frame_count):
            frame[:, 2] = 0.01 + amplitude * np.sin(2 * np.pi * (rest[:, 0] - speed * f) / wavelength)
            out.write(frame.astype("<f4").tobytes())
    scene.write_pc2(path("floor.pc2"), [floor] * frame_count)


if __name__ == "__main__":
    main()
