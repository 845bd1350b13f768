#!/usr/bin/python3
"""Writes the bad-input corpus (tests/corpus/files). Run once; the files are committed. Keep it reproducible."""
import os
import struct

import numpy as np

D = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'files')
os.makedirs(D, exist_ok=True)


def w(name, data, mode='w'):
    with open(os.path.join(D, name), mode) as f:
        f.write(data)


def binary_stl(tris, count=None):
    out = b'binary stl written by make_corpus.py'.ljust(80, b' ')
    out += struct.pack('<I', len(tris) if count is None else count)
    for t in tris:
        out += struct.pack('<3f', 0, 0, 1) + b''.join(struct.pack('<3f', *v) for v in t) + b'\0\0'
    return out


tet = [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (0, 0, 1)), ((0, 0, 0), (0, 0, 1), (0, 1, 0)),
       ((1, 0, 0), (0, 1, 0), (0, 0, 1))]


def ascii_stl(tris):
    s = 'solid t\n'
    for t in tris:
        s += 'facet normal 0 0 1\nouter loop\n' + ''.join('vertex %s %s %s\n' % v for v in t) + 'endloop\nendfacet\n'
    return s + 'endsolid t\n'


w('empty.stl', '')
w('truncated_binary.stl', binary_stl(tet, count=100), 'wb')
w('count_mismatch.stl', binary_stl(tet + tet, count=2), 'wb')
w('garbage_ascii.stl', 'solid x\nhello world\nfacet normal 0 0 1\n')
w('nan.stl', ascii_stl([((0, 0, 0), (1, 0, 'nan'), (0, 1, 0))] + tet[1:]))
w('inf.stl', ascii_stl([((0, 0, 0), (1, 0, 'inf'), (0, 1, 0))] + tet[1:]))
w('degenerate.stl', ascii_stl([((0, 0, 0), (0, 0, 0), (1, 1, 1)), ((1, 0, 0), (1, 0, 0), (0, 1, 1))]))
w('single_triangle.stl', ascii_stl([((0, 0, 0), (1, 0, 0), (0, 1, 0))]))
w('binary_nan.stl', binary_stl([((0, 0, 0), (1, 0, float('nan')), (0, 1, 0))] + tet[1:]), 'wb')
w('short_header.stl', b'\x01\x02\x03', 'wb')
w('plane.obj', 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n')
w('open_sheet.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n')
w('bad_index.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 10\n')
w('no_faces.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\n')
w('malformed.off', 'OFF\n3 1 0\n0 0 0\n')
w('malformed.ply', 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n0\n')
w('grain.xyz', '0 0 0\n')
w('empty.ply', '')
np.save(os.path.join(D, 'flat_2d.npy'), np.ones((4, 4), dtype=bool))
np.save(os.path.join(D, 'float.npy'), np.ones((4, 4, 4), dtype=np.float32))
np.save(os.path.join(D, 'empty_shape.npy'), np.zeros((4, 0, 4), dtype=bool))
np.save(os.path.join(D, 'all_zero.npy'), np.zeros((4, 4, 4), dtype=np.uint8))
np.save(os.path.join(D, 'full.npy'), np.ones((4, 4, 4), dtype=bool))  # valid: solid to its border
with open(os.path.join(D, 'full.npy'), 'rb') as f:
    data = f.read()
w('truncated.npy', data[:-20], 'wb')
w('bad_magic.npy', b'NOTNUMPY' + b'\0' * 100, 'wb')
w('bad_radius.csv', 'x,y,z,r\n0,0,0,-1\n')
w('not_numbers.csv', 'x,y,z,r\n0,0,zero,1\n')
w('no_spheres.csv', 'x,y,z,r\n')
two = np.zeros((8, 8, 8), dtype=np.int16)
two[1:4, 1:4, 1:4] = 1
two[5:8, 5:8, 5:8] = 2
np.save(os.path.join(D, 'two_labels.npy'), two)  # without --label the grains would merge
w('bad_byte.csv', b'x,y,z,r\n0,0,\xb5,1\n', 'wb')  # not UTF-8: the message quotes it
w('two_clumps.txt', '0 0 0 1 0\n1 0 0 1 0\n5 0 0 1 7\n')
