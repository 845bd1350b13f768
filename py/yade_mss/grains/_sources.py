"""Sources of a grain: a mesh file, a voxel file, an array, (vertices, triangles); their mass properties."""

import math
import os

import numpy as np

from .. import _mss
from ..base import cppPath, integer, memoryBytes, number, optional, requireRegularFile, vector3
from ._results import MassProperties
from ._volumes import readVolume

# the format table's (pkg/mss/io/formats.cpp)
MESH_EXT = tuple(f['extension'] for f in _mss.fileFormats() if f['kind'] == 'mesh')


def flatArray(a, dtype=float):
    """A flat contiguous array of *a* for the binding, which reads its buffer at once (a list is read one
    element at a time)."""
    return np.ascontiguousarray(a, dtype=dtype).ravel()


def _rows3(what, a, dtype=None):
    """*a* as rows of 3 (n, 3), or a message naming *what* and the shape given (numpy's reshape error named
    neither)."""
    if a is None:
        raise TypeError('mesh: %s are missing (None); give an array of shape (n, 3)' % what)
    try:
        a = np.asarray(a, dtype=dtype)
    except (TypeError, ValueError) as e:
        raise TypeError('mesh: %s must be numbers (an array of shape (n, 3)), got %s (%s)'
                        % (what, type(a).__name__, e)) from None
    if a.dtype == object or a.ndim not in (1, 2) or (a.ndim == 2 and a.shape[1] != 3) or a.size % 3:
        raise ValueError('mesh: %s must have shape (n, 3) (or 3n numbers), got shape %s'
                         % (what, 'x'.join(str(n) for n in a.shape) or 'scalar'))
    return a.reshape(-1, 3)


class Mesh(object):
    def __init__(self, vertices, triangles, name):
        self.vertices = _rows3('vertices', vertices, float)
        self.triangles = _rows3('triangles', triangles)
        if self.triangles.size and not np.issubdtype(self.triangles.dtype, np.integer):
            if not np.all(np.mod(self.triangles, 1) == 0):
                raise ValueError('mesh: triangle indices must be integers')
        self.triangles = self.triangles.astype(np.int64)
        self.name = name

    def args(self):
        return flatArray(self.vertices), flatArray(self.triangles, np.int64)


def _labelList(labels):
    shown = ', '.join(str(int(x)) for x in labels[:20])
    return shown + (', ...' if len(labels) > 20 else '')


# bytes a voxel while a volume becomes the core's grid here (a comparison, the solid, its bytes, the copy)
_BYTES_PER_VOXEL = 4


def _checkVolumeSize(a):
    """The memory guard, before any work on *a*: sized by its shape, which a view (a broadcast, a memory map,
    a strided slice) does not hold in memory but every step below would."""
    shape = 'x'.join(str(n) for n in a.shape)
    if a.size > 2 ** 31 - 1:
        raise ValueError('voxels: a volume of %s voxels (%.3g) has over 2^31 - 1 voxels, more than a grid can '
                         'index: crop it to the grain, or give the labelled volume to batch (it reads it in slabs)'
                         % (shape, a.size))
    need, limit = a.size * _BYTES_PER_VOXEL, memoryBytes() // 2
    if need > limit:
        raise ValueError('voxels: a volume of %s voxels would need %.3g GiB here, more than half the memory '
                         '(%.3g GiB): crop it to the grain' % (shape, need / 2.0 ** 30, limit / 2.0 ** 30))


class _Voxels(object):
    def __init__(self, array, voxelSize, origin, name, label=None):
        a = np.asarray(array)
        if a.ndim != 3:
            raise ValueError('voxels: the array must be 3-D, got %d-D' % a.ndim)
        if a.size == 0:
            raise ValueError('voxels: the array is empty')
        _checkVolumeSize(a)
        if not (a.dtype == bool or np.issubdtype(a.dtype, np.integer)):
            raise ValueError('voxels: dtype %s is not boolean or integer (threshold a grey-level volume first)' % a.dtype)
        if a.dtype != bool and a.min() < 0:
            raise ValueError('voxels: the volume holds negative values (%d): labels are >= 0 (0 is background)'
                             % a.min())
        if label is None and a.dtype != bool:
            labels = np.unique(a[a != 0])
            if len(labels) > 1:  # the grains would merge into one solid
                raise ValueError('voxels: the volume holds %d labels (%s): choose one grain with label='
                                 % (len(labels), _labelList(labels)))
        solid = (a == label) if label is not None else (a != 0)
        if not solid.any():
            raise ValueError('voxels: no voxel has label %s' % label if label is not None else 'voxels: the volume has no solid voxel')
        self.shape = solid.shape
        self.data = np.asfortranarray(solid.astype(np.uint8)).tobytes(order='F')  # x fastest
        self.voxelSize = 1.0 if voxelSize is None else float(voxelSize)
        if not (self.voxelSize > 0 and math.isfinite(self.voxelSize)):
            raise ValueError('voxels: voxel size must be > 0 and finite, got %s' % voxelSize)
        self.origin = [float(x) for x in (origin if origin is not None else (0, 0, 0))]
        if len(self.origin) != 3:
            raise ValueError('voxels: origin must have 3 coordinates')
        self.name = name

    def args(self):
        return self.data, tuple(int(n) for n in self.shape), self.voxelSize, self.origin


def readGrain(source, voxelSize=None, origin=None, label=None, scale=None):
    """A mesh or voxel source from a file name, an array, (vertices, triangles) or a dict; *scale* multiplies
    its coordinates as read (a mesh's vertices, a volume's voxel size and origin)."""
    voxelSize = optional(number, 'grain', 'voxelSize', voxelSize)
    origin = optional(vector3, 'grain', 'origin', origin)
    label = optional(integer, 'grain', 'label', label, 0)
    scale = optional(number, 'grain', 'scale', scale, finite=False)
    s = _unscaled(source, voxelSize, origin, label)
    if scale is None or scale == 1.0:
        return s
    k = scale
    if isinstance(s, Mesh):
        v = np.asarray(s.vertices, dtype=float)
        extent = float(np.ptp(v, axis=0).max()) if v.size else 0.0
        _checkScaled(k, extent * k, float(np.abs(v).max()) * k if v.size else 0.0, 'the mesh\'s extent %g' % extent)
        s.vertices = v * k
    else:
        _checkScaled(k, s.voxelSize * k, max([abs(x) for x in s.origin] + [0.0]) * k,
                     'the voxel edge %g' % s.voxelSize)
        s.voxelSize *= k
        s.origin = [k * x for x in s.origin]
    return s


# below this, a length has lost its digits (a subnormal double has fewer than 52 bits): a grain that small
# voxelises to nothing and its triangles read as degenerate
TINY = 1e-290
HUGE = 1e60  # the C++ core's bound on a coordinate


def _checkScaled(scale, size, far, what):
    """Refuses a scale that makes a grain's coordinates too large or its size underflow, naming the scale (not a
    non-finite vertex or a degenerate mesh, which a good file is not)."""
    if not np.isfinite(size) or not far <= HUGE:
        raise ValueError('scale %g: %s times the scale reaches %g, beyond %g (where a grain\'s inertia, as size^5, '
                         'overflows): scale is the unit conversion of the coordinates (1e-3 for millimetres to '
                         'metres)' % (scale, what, far, HUGE))
    if size < TINY:
        raise ValueError('scale %g: %s times the scale is %g, under %g: the grain would vanish; scale is the '
                         'unit conversion of the coordinates (1e-3 for millimetres to metres)'
                         % (scale, what, size, TINY))


def _unscaled(source, voxelSize=None, origin=None, label=None):
    if isinstance(source, (str, os.PathLike)):
        path = os.fspath(source)
        requireRegularFile('readMesh' if os.path.splitext(path)[1].lower() in MESH_EXT else 'read', path)
        ext = os.path.splitext(path)[1].lower()
        if ext in MESH_EXT:
            with cppPath(path) as p:
                v, t = _mss.readMesh(p)
            return Mesh(v, t, os.path.basename(path))
        if ext == '.npy':  # the C++ reader: its checks and messages, as in the mss command
            with cppPath(path) as p:
                data, shape = _mss.readNpy(p, -1 if label is None else int(label))
            a = np.frombuffer(data, dtype=np.uint8).reshape(shape, order='F')
            return _Voxels(a, voxelSize, origin, os.path.basename(path))
        if ext in ('.tif', '.tiff'):  # a TIFF stack, as mssAssembly and mss batch read it
            return _Voxels(readVolume(path), voxelSize, origin, os.path.basename(path), label)
        raise ValueError("%s: unknown mesh extension '%s' (expected a mesh: .stl, .obj, .off, .ply; or voxels: .npy, "
                         ".tif, .tiff)" % (path, ext))
    if isinstance(source, dict) and 'vertices' in source and 'triangles' in source:
        return Mesh(source['vertices'], source['triangles'], 'mesh')
    if isinstance(source, tuple) and len(source) == 2:
        return Mesh(source[0], source[1], 'mesh')
    if isinstance(source, np.ndarray):
        return _Voxels(source, voxelSize, origin, 'array', label)
    raise ValueError('source must be a mesh file, a .npy file, a 3-D numpy array, (vertices, triangles) or an '
                     'MssResult; got %s' % type(source).__name__)


def planeList(func, value):
    """A list of planes, each :func:`checkedPlane`; not a string, not one object that is no list."""
    if isinstance(value, (str, bytes)) or not hasattr(value, '__iter__'):
        raise TypeError('%s: planes must be a list of ((px, py, pz), (nx, ny, nz)), got %r' % (func, value))
    return [checkedPlane(p) for p in value]


def checkedPlane(p):
    """A plane ((px, py, pz), (nx, ny, nz)) as the binding takes it, 6 floats, or a ValueError naming it."""
    try:
        point, normal = p
        v = [float(x) for x in point] + [float(x) for x in normal]
    except (TypeError, ValueError):
        raise ValueError('planes: each plane is ((px, py, pz), (nx, ny, nz)), got %r' % (p,))
    if len(v) != 6:
        raise ValueError('planes: each plane is ((px, py, pz), (nx, ny, nz)), got %r' % (p,))
    return v


def massProperties(source, voxelSize=None, origin=None, label=None, planes=()):
    """:class:`MassProperties` (unit density) of a mesh (exact, divergence theorem) or voxels (exact voxel sums).
    With ``planes`` (as in :func:`generate`): of the part on their allowed side, a fragment (a mesh cut and capped
    exactly; voxels whose centre is on that side).

    :param source: a mesh file, voxel file, array or (vertices, triangles), as :func:`generate` takes
    :param float voxelSize: a voxel volume's voxel edge (world units; default 1)
    :param origin: a voxel volume: the centre of voxel (0, 0, 0), 3 numbers
    :param int label: a labelled volume: the grain's label
    :param planes: planes as in :func:`generate`, ((px, py, pz), (nx, ny, nz)) each
    :return: :class:`MassProperties`
    """
    s = readGrain(source, voxelSize, origin, label)
    cuts = planeList('massProperties', planes)
    if isinstance(s, Mesh):
        return MassProperties._fromDict(_mss.massMesh(*s.args(), cuts))
    return MassProperties._fromDict(_mss.massVoxels(*s.args(), cuts))
