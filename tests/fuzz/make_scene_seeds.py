#!/usr/bin/env python3
"""Writes the scene fuzzer's seeds (tests/fuzz/corpus/scene): byte strings
that fuzz_scene.c decodes into sensible scenes, so that the fuzzer starts
from runs that reach the solver. The encoding is fuzz_input.h's and
fuzz_scene.c's: a double is a selector byte and its bytes, an operation is
a fluid-id byte, an operation byte and its arguments."""
import os
import struct
import sys

AWKWARD = {0.01: 4, 0.02: 5, 0.05: 6, 0.1: 7, 1000.0: 22, 1e-6: 23, 0.97: 21, 2.1: 19}


def d(value):
    if value in AWKWARD:
        return bytes([0, AWKWARD[value]])
    return bytes([2]) + struct.pack(">h", round(value * 100))


def op(code, *args, fluid=1):
    return bytes([fluid, code]) + b"".join(args)


def fluid(name_index=0):
    return op(0, d(1000.0), d(1e-6), bytes([name_index]))


def fluid_box(x0, y0, x1, y1):
    return op(1, d(x0), d(y0), d(x1), d(y1))


def wall_box(x0, y0, x1, y1):
    return op(2, d(x0), d(y0), d(x1), d(y1))


def tank(x0, y0, x1, y1, open_top=1):
    return op(3, d(x0), d(y0), d(x1), d(y1), bytes([open_top]))


def option(key, value):
    return op(6, bytes([key, value]))


def param(index, value):
    return op(5, bytes([index]), d(value))


def particles(points):
    body = bytes([len(points)])
    for x, y in points:
        body += d(x) + d(y) + d(0.0) + d(0.0) + bytes([1, 1])  # fluid, id 0
    return op(4, body + bytes([0]))


SEEDS = {
    "dam-break": d(0.02) + fluid() + fluid_box(0, 0, 0.1, 0.1) + tank(0, 0, 0.2, 0.2),
    "cg-closed": d(0.02) + fluid() + fluid_box(0, 0, 0.1, 0.06) + tank(0, 0, 0.1, 0.1, 0)
    + option(0, 1),
    "two-fluids": d(0.05) + fluid() + fluid(1) + fluid_box(0, 0, 0.2, 0.2)
    + op(1, d(0.2), d(0), d(0.4), d(0.2), fluid=2) + tank(0, 0, 0.4, 0.4),
    "walls-params": d(0.05) + fluid() + wall_box(-0.2, -0.2, 0.7, 0) + fluid_box(0, 0, 0.5, 0.3)
    + param(2, 0.97) + param(0, 2.1) + option(1, 3) + option(2, 6),
    "particles": d(0.1) + fluid() + particles([(0, 0), (0.1, 0), (0, 0.1), (0.1, 0.1)])
    + wall_box(-0.3, -0.3, 0.4, -0.05),
}

if __name__ == "__main__":
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus", "scene")
    os.makedirs(out, exist_ok=True)
    for name, data in SEEDS.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
