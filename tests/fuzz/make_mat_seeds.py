#!/usr/bin/env python3
"""Writes the seed corpus of the .mat harness (tests/fuzz/corpus/mat/): small MATLAB level 4 and
level 5 files in both byte orders, compressed and not, with the variable kinds the reader reads
(real numeric vectors of every storage type) and those it skips (scalars, matrices, complex, char,
cell, struct). Standard library only, following MathWorks' "MAT-File Format" document.

    python3 tests/fuzz/make_mat_seeds.py tests/fuzz/corpus/mat
"""
import os
import struct
import sys
import zlib

MI = {"int8": 1, "uint8": 2, "int16": 3, "uint16": 4, "int32": 5, "uint32": 6, "single": 7,
      "double": 9, "int64": 12, "uint64": 13, "matrix": 14, "compressed": 15, "utf8": 16}
FMT = {"int8": "b", "uint8": "B", "int16": "h", "uint16": "H", "int32": "i", "uint32": "I",
       "single": "f", "double": "d", "int64": "q", "uint64": "Q"}
MX = {"cell": 1, "struct": 2, "char": 4, "double": 6, "single": 7, "int8": 8, "uint8": 9,
      "int16": 10, "uint16": 11, "int32": 12, "uint32": 13, "int64": 14, "uint64": 15}


def pad8(b):
    return b + b"\0" * ((8 - len(b) % 8) % 8)


def element(bo, mi_type, payload):
    if 0 < len(payload) <= 4 and mi_type != MI["matrix"]:  # small data element format
        return struct.pack(bo + "I", (len(payload) << 16) | mi_type) + payload.ljust(4, b"\0")
    return struct.pack(bo + "II", mi_type, len(payload)) + pad8(payload)


def numbers(bo, kind, values):
    return element(bo, MI[kind], struct.pack(bo + FMT[kind] * len(values), *values))


def matrix(bo, name, mx_class, dims, parts, flags=0):
    body = element(bo, MI["uint32"], struct.pack(bo + "II", mx_class | flags, 0))
    body += element(bo, MI["int32"], struct.pack(bo + "i" * len(dims), *dims))
    body += element(bo, MI["int8"], name.encode())
    for p in parts:
        body += p
    return struct.pack(bo + "II", MI["matrix"], len(body)) + body


def v5(bo, variables, compress=False):
    header = b"MATLAB 5.0 MAT-file, written by make_mat_seeds.py".ljust(116, b" ")
    header += b"\0" * 8 + struct.pack(bo + "H", 0x0100) + struct.pack(bo + "H", 0x4D49)
    out = header
    for v in variables:
        if compress:
            z = zlib.compress(v)
            out += struct.pack(bo + "II", MI["compressed"], len(z)) + z
        else:
            out += v
    return out


def v4(bo, name, rows, cols, values, precision=0, imag=False):
    m = 0 if bo == "<" else 1
    kind = "dfihHB"[precision]
    head = struct.pack(bo + "iiiii", m * 1000 + precision * 10, rows, cols, 1 if imag else 0, len(name) + 1)
    data = struct.pack(bo + kind * len(values), *values)
    return head + name.encode() + b"\0" + data + (data if imag else b"")


def main(folder):
    os.makedirs(folder, exist_ok=True)
    seeds = {}
    for bo, tag in (("<", "le"), (">", "be")):
        t = [0.0, 0.1, 0.2, 0.3]
        u = [1.0, -2.0, 0.5, 3.0]
        plain = [
            matrix(bo, "t", MX["double"], [4, 1], [numbers(bo, "double", t)]),
            matrix(bo, "u", MX["double"], [1, 4], [numbers(bo, "int16", [1, -2, 0, 3])]),
            matrix(bo, "y", MX["single"], [4, 1], [numbers(bo, "single", u)]),
            matrix(bo, "gain", MX["double"], [1, 1], [numbers(bo, "double", [2.0])]),
        ]
        skipped = [
            matrix(bo, "M", MX["double"], [2, 2], [numbers(bo, "double", [1, 2, 3, 4])]),
            matrix(bo, "z", MX["double"], [4, 1], [numbers(bo, "double", t), numbers(bo, "double", u)], flags=0x800),
            matrix(bo, "label", MX["char"], [1, 5], [numbers(bo, "uint16", [104, 101, 108, 108, 111])]),
            matrix(bo, "c", MX["cell"], [1, 1], [matrix(bo, "", MX["double"], [1, 2], [numbers(bo, "uint8", [1, 2])])]),
        ]
        ints = [matrix(bo, k, MX[k], [1, 3], [numbers(bo, k, [1, 2, 3])]) for k in FMT if k not in ("single", "double")]
        seeds[f"v5_{tag}.mat"] = v5(bo, plain)
        seeds[f"v5_{tag}_compressed.mat"] = v5(bo, plain, compress=True)
        seeds[f"v5_{tag}_skipped.mat"] = v5(bo, plain[:2] + skipped, compress=(bo == "<"))
        seeds[f"v5_{tag}_integers.mat"] = v5(bo, ints)
        seeds[f"v4_{tag}.mat"] = (v4(bo, "t", 4, 1, t) + v4(bo, "u", 1, 4, [1, -2, 0, 3], precision=3)
                                  + v4(bo, "y", 4, 1, u, precision=1) + v4(bo, "z", 4, 1, u, imag=True))
    for name, data in seeds.items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(data)
    print(f"{len(seeds)} seeds in {folder}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "corpus", "mat"))
