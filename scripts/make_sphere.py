#!/usr/bin/env python3
"""Writes make_uv_sphere(N)'s mesh (host/scene/procedural.cpp: the same stacks, segments, vertex
order and triangles; positions through Python's math, so possibly a last bit apart) as a binary
little-endian PLY, with nothing but the standard library.

    make_sphere.py TRIANGLES OUT.ply

Used by scripts/memory_check.sh and tests/memory_check.cmake.
"""
import math
import struct
import sys
from array import array


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: make_sphere.py TRIANGLES OUT.ply")
    t = float(max(8, int(sys.argv[1])))
    stacks = max(2, int(math.floor((1 + math.sqrt(1 + t)) / 2 + 0.5)))
    seg = max(4, int(math.floor(t / (2 * (stacks - 1)) + 0.5)))
    pos = array('f', [0.0, 1.0, 0.0])
    for i in range(1, stacks):
        th = i / (2.0 * stacks) * 2 * math.pi
        st, ct = math.sin(th), math.cos(th)
        for j in range(seg):
            ph = j / float(seg) * 2 * math.pi
            pos.extend((st * math.cos(ph), ct, st * math.sin(ph)))
    pos.extend((0.0, -1.0, 0.0))
    south = 1 + (stacks - 1) * seg

    def ring(i, j):
        return 1 + (i - 1) * seg + j % seg

    # A face: one count byte and three uint32 indices (13 bytes), written in blocks.
    face = struct.Struct('<BIII')
    out = bytearray()
    for j in range(seg):
        out += face.pack(3, 0, ring(1, j + 1), ring(1, j))
    for i in range(1, stacks - 1):
        for j in range(seg):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            out += face.pack(3, a, d, c)
            out += face.pack(3, a, b, d)
    for j in range(seg):
        out += face.pack(3, south, ring(stacks - 1, j), ring(stacks - 1, j + 1))
    faces = len(out) // face.size
    if sys.byteorder != 'little':
        pos.byteswap()
    with open(sys.argv[2], 'wb') as f:
        f.write(('ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n'
                 'property float y\nproperty float z\nelement face %d\n'
                 'property list uchar uint vertex_indices\nend_header\n' % (len(pos) // 3, faces)).encode())
        f.write(pos.tobytes())
        f.write(out)
    print(len(pos) // 3, 'vertices', faces, 'triangles')


if __name__ == '__main__':
    main()
