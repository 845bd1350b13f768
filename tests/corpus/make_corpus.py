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

# hostile files: readers that trusted a header, rows read as comments, ids merged, valid files refused
full = np.ones((4, 4, 4), dtype=np.uint8)


def npy(header_text, payload=b'', version=1):
    h = header_text.encode('latin1')
    if version == 1:
        pad = 64 - (10 + len(h) + 1) % 64
        return b'\x93NUMPY\x01\x00' + struct.pack('<H', len(h) + pad % 64 + 1) + h + b' ' * (pad % 64) + b'\n' + payload
    pad = 64 - (12 + len(h) + 1) % 64
    return b'\x93NUMPY\x02\x00' + struct.pack('<I', len(h) + pad % 64 + 1) + h + b' ' * (pad % 64) + b'\n' + payload


dict_u8 = "{'descr': '|u1', 'fortran_order': False, 'shape': (4, 4, 4), }"
w('big_header_valid.npy', npy(dict_u8 + ' ' * 30000, full.tobytes()), 'wb')  # ~30 KB: crashed std::regex
w('huge_header.npy', npy(dict_u8 + ' ' * 200000, full.tobytes(), version=2), 'wb')
w('nested_header.npy', npy('{' * 20000 + '}' * 20000, full.tobytes(), version=2), 'wb')
w('huge_shape.npy', npy("{'descr': '|u1', 'fortran_order': False, 'shape': (100000, 100000, 100000), }", b'\1' * 64),
  'wb')
w('overflow_shape.npy', npy("{'descr': '<i8', 'fortran_order': False, 'shape': (4294967296, 4294967296, 4294967296)"
                            ", }", b'\1' * 64), 'wb')
w('negative_shape.npy', npy("{'descr': '|u1', 'fortran_order': False, 'shape': (4, -4, 4), }", full.tobytes()), 'wb')
w('unicode_descr.npy', npy("{'descr': '<U4', 'fortran_order': False, 'shape': (4, 4, 4), }", b'\0' * 1024), 'wb')
w('object_descr.npy', npy("{'descr': '|O', 'fortran_order': False, 'shape': (4, 4, 4), }", b'\0' * 512), 'wb')
w('big_endian_valid.npy', npy("{'descr': '>i2', 'fortran_order': False, 'shape': (4, 4, 4), }",
                              full.astype('>i2').tobytes()), 'wb')
w('nan_row.csv', 'x,y,z,r\nnan,0,0,1\n0,0,0,1\n')
w('inf_row.csv', 'x,y,z,r\ninf,0,0,1\n0,0,0,1\n')
w('infinity_radius.csv', 'x,y,z,r\n0,0,0,Infinity\n')
w('bom_valid.csv', '\ufeffx,y,z,r\n0,0,0,0.4\n0.1,0,0,0.3\n')  # inside tests/data/cube.stl
w('bom_first_row.csv', '\ufeff0,0,0,0.4\n0.1,0,0,0.3\n')
w('inside.csv', 'x,y,z,r\n0,0,0,0.4\n0.1,0,0,0.3\n')
w('fraction_ids.txt', '0 0 0 1 1.5\n1 0 0 1 2.5\n')
w('negative_ids.txt', '0 0 0 1 -1\n1 0 0 1 -2\n')
w('huge_ids.txt', '0 0 0 1 1e16\n1 0 0 1 10000000000000001\n')
w('no_endsolid.stl', ascii_stl(tet).replace('endsolid t\n', ''))
w('utf8_solid_valid.stl', ascii_stl(tet).replace('solid t', 'solid grain_\u00e9\u00e8').replace('endsolid t',
                                                                                                'endsolid grain'))
w('faces_first_valid.ply', 'ply\nformat ascii 1.0\nelement face 4\nproperty list uchar int vertex_indices\n'
  'element vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n'
  '3 0 1 2\n3 0 2 3\n3 0 3 1\n3 1 3 2\n0 0 0\n0 1 0\n1 0 0\n0 0 1\n')
w('huge_vertex_count.ply', 'ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\n'
  'property float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n')
w('truncated_binary.ply', b'ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n'
  b'property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n'
  + b'\0' * 30, 'wb')
w('index_zero.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 0 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n')
w('huge_coordinates.obj', 'v 0 0 0\nv 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n')
w('zero_triangles.stl', binary_stl([], count=0), 'wb')
w('huge_count.off', 'OFF\n99999999999 99999999999 0\n0 0 0\n')
w('vtk_bad_points.vtk', '# vtk DataFile Version 3.0\nspheres\nASCII\nDATASET POLYDATA\nPOINTS 1000000000 double\n'
  '0 0 0\n')
# other codes' clump templates (mss export writes them; readSpheres reads them back)
w('template_short.in', 'fix t all particletemplate/multisphere 15485863 nspheres 1000000 ntry 10 spheres &\n'
  '    0 0 0 1 &\n    type 1\n')
w('template_file.in', 'fix t all particletemplate/multisphere 15485863 nspheres 2 ntry 10 spheres file p.txt type 1\n')
w('template_bad_rotation.in', '#   c = 0 0 0\n#   R = 1 0 0 ; 0 1 0 ; 0 0 -1 (rows)\nfix t all '
  'particletemplate/multisphere 15485863 nspheres 1 ntry 10 spheres 0 0 0 1 type 1\n')
w('cluster_unended.clu', 'Name\nx\nBegin centers_and_radii\n0 0 0 1\n1 0 0 1\n')
w('cluster_inf.clu', 'Begin centers_and_radii\n0 0 0 inf\nEnd centers_and_radii\n')
w('pfc_short.p3dat', "clump template create name 'x' ...\n    pebbles 1000000 ...\n    1 0 0 0 ...\n    volume 1\n")
w('pfc_bubblepack.p3dat', "clump template create name 'x' geometry 'g' bubblepack distance 120 surfcalculate\n")
w('yade_export_bad_row.txt', '# written by mss export --format yade from x.stl\n0 0 0 1 0\n1 0 0\n')
w('header_lacks_z.csv', 'x,y,radius,q\n1,2,0.5,3\n')
w('header_twice_x.csv', 'x,x,y,z,r\n1,1,2,3,0.5\n')
# messages that name the value and the line; sphere files at the ends of the double range; heavy requests
w('obj_number_out_of_range.obj', 'v 0 0 1e999\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n')
w('obj_negative_index.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 -9\n')
_ply_head = ('ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n'
             'element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n')
w('ply_bad_list_length.ply', _ply_head + '3 0 1 2\n-3 0 1 3\n')
w('ply_list_ends_early.ply', _ply_head + '3 0 1 2\n3 0 1\n')
with open(os.path.join(D, 'npy_structured.npy'), 'wb') as f:
    np.save(f, np.zeros((4, 4, 4), dtype=[('a', 'u1'), ('b', '<f4')]))
w('huge_radius.csv', 'x,y,z,r\n0.5,0.5,0.5,1e300\n')
w('denormal_radius.csv', 'x,y,z,r\n0.5,0.5,0.5,1e-310\n0.6,0.5,0.5,1e-310\n')
w('one_sphere.csv', 'x,y,z,r\n0.5,0.5,0.5,0.5\n')
_tet_faces = '3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n'
w('homogeneous_zero_w.off', '4OFF\n4 4 0\n0 0 0 0\n1 0 0 1\n0 1 0 1\n0 0 1 1\n' + _tet_faces)
w('dimension_four.off', 'nOFF\n4\n4 4 0\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n' + _tet_faces)
w('tiny_on_unit.csv', 'x,y,z,r\n0,0,0,1\n1,0,0,1e-9\n')
_cube8 = ''.join('v %d %d %d\n' % (i & 1, (i >> 1) & 1, (i >> 2) & 1) for i in range(8))
w('polygon_repeats.obj', _cube8 + 'f ' + ' '.join(str(1 + i % 8) for i in range(24)) + '\n')
w('repeated_faces.obj', 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n' + 'f 2 3 4\n' * 50)
_disc = np.zeros((20, 20), dtype=np.uint8)
_disc[5:15, 5:15] = 1
np.save(os.path.join(D, 'square_2d.npy'), _disc)
# a triangle soup: 2000 triangles of random corners in a cube, every ray of a grid crossing hundreds of them
_rng = np.random.default_rng(7)
w('triangle_soup.obj', ''.join('v %.4f %.4f %.4f\n' % tuple(v) for v in _rng.random((6000, 3)))
  + ''.join('f %d %d %d\n' % (3 * i + 1, 3 * i + 2, 3 * i + 3) for i in range(2000)))
