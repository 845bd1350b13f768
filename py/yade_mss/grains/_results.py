"""Results and sphere files: :class:`MassProperties`, :class:`MssResult`, :func:`readSpheres`."""

import json
import os
import struct
import zipfile
import zlib

import numpy as np

from .. import _mss
from ..base import INT64_MAX, atomicWrite, flag, integer, number, split, vector3


class MassProperties(object):
    """Volume, centroid and inertia tensor (about the centroid, world axes) of a solid of unit density.

    :param float volume: the volume (world units cubed)
    :param centroid: the centre of mass, 3 numbers
    :param inertia: the inertia tensor about the centroid for unit density, 3x3 (world axes)
    """

    def __init__(self, volume, centroid, inertia):
        self.volume = float(volume)
        self.centroid = np.asarray(centroid, dtype=float).reshape(3)
        self.inertia = np.asarray(inertia, dtype=float).reshape(3, 3)

    @staticmethod
    def _fromDict(d):
        return MassProperties(d['volume'], d['centroid'], d['inertia'])

    def principal(self):
        """Principal moments (ascending) and axes (columns of a rotation matrix)."""
        w, v = np.linalg.eigh(self.inertia)
        if np.linalg.det(v) < 0:
            v[:, 2] = -v[:, 2]
        return w, v

    def transformed(self, scale=1.0, rotation=None, center=None):
        """The same solid scaled about its centroid, rotated, moved.

        :param float scale: length factor (volume grows as scale^3, inertia as scale^5)
        :param rotation: 3x3 rotation matrix (default: none)
        :param center: the new centroid, 3 numbers (default: where it is)
        :return: :class:`MassProperties`
        """
        R = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
        c = self.centroid if center is None else np.asarray(center, dtype=float)
        return MassProperties(self.volume * scale ** 3, c, scale ** 5 * R.dot(self.inertia).dot(R.T))

    def _toDict(self):
        return {'volume': self.volume, 'centroid': self.centroid.tolist(), 'inertia': self.inertia.ravel().tolist()}


# the templates whose extension names their code and that need no density (mss generate -o writes them too)
TEMPLATE_EXTENSIONS = {'.clu': 'kratos', '.p3dat': 'pfc'}

class MssResult(object):
    """A sphere set and where it came from: what :func:`generate` returns and :func:`mssClump` accepts.

    :param centers: sphere centres, (n, 3), world units
    :param radii: sphere radii, (n,), finite and > 0
    :param dict metrics: figures of the generation (see ``metrics`` below)
    :param dict grid: the generation grid (dims, voxelSize, origin), or None
    :param targetMass: :class:`MassProperties` of the target, or None
    :param str source: what it was made from (a file name, 'array')

    :ivar centers: sphere centres, numpy array (n, 3), world units
    :ivar radii: sphere radii, numpy array (n,)
    :ivar metrics: dict of figures on the generation grid (spheres, eta, dice, protrusion: the largest beyond the
        grain in world units, an upper bound; protrusionLimit: the bound that applied; smallestRadius, world units:
        what sets the time step, see :meth:`timeStep`; iterations, seconds...)
    :ivar grid: dict (dims, voxelSize, origin) of the generation grid, or None
    :ivar targetMass: :class:`MassProperties` of the target solid (unit density), or None if unknown
    :ivar source: description of the input (file name or 'array')
    """

    def __init__(self, centers, radii, metrics=None, grid=None, targetMass=None, source=''):
        try:
            c, r = np.asarray(centers, dtype=float), np.asarray(radii, dtype=float)
        except (TypeError, ValueError):
            raise TypeError('MssResult: centres must be an (n, 3) array of numbers and radii n numbers') from None
        if not ((c.ndim == 2 and c.shape[1] == 3) or (c.ndim == 1 and c.size % 3 == 0)) or r.ndim > 1:
            raise ValueError('MssResult: centres must be an (n, 3) array and radii n numbers, got shapes %s and %s'
                             % (c.shape, r.shape))
        self.centers = c.reshape(-1, 3)
        self.radii = r.reshape(-1)
        if len(self.centers) != len(self.radii):
            raise ValueError('MssResult: %d centres but %d radii' % (len(self.centers), len(self.radii)))
        if not (np.all(np.isfinite(self.centers)) and np.all(np.isfinite(self.radii)) and np.all(self.radii > 0)):
            raise ValueError('MssResult: centres must be finite numbers and radii finite numbers > 0 (%d not finite, '
                             '%d radii <= 0)' % (int(np.sum(~np.isfinite(self.centers).all(axis=1))
                                                    + np.sum(~np.isfinite(self.radii))),
                                                 int(np.sum(self.radii <= 0))))
        self.metrics = dict(metrics or {})
        self.grid = grid
        self.targetMass = targetMass
        self.source = source
        self.grain = None  # what it was generated from (a path, an array, (vertices, triangles)); not saved
        self._unionMass = None

    def __len__(self):
        return len(self.radii)

    def __repr__(self):
        return '<MssResult %d spheres from %s, dice %s>' % (len(self), self.source or '?', self.metrics.get('dice', '?'))

    def unionMass(self, resolution=200):
        """:class:`MassProperties` of the union of the spheres (overlaps counted once), unit density.

        :param int resolution: voxels along the union's shortest edge for the parts where spheres overlap
            (the rest is exact)
        """
        resolution = integer('MssResult.unionMass', 'resolution', resolution, 2)
        if self._unionMass is None or self._unionMass[0] != resolution:
            d = _mss.massSpheres(self.centers.ravel().tolist(), self.radii.tolist(), resolution)
            self._unionMass = (resolution, MassProperties._fromDict(d))
        return self._unionMass[1]

    def unionVolume(self):
        """The exact volume of the union of the spheres (overlaps counted once): the divergence theorem over each
        sphere's exposed surface (C++ ``mss::sphereUnionVolume``), to near machine precision."""
        return _mss.sphereUnionVolume(self.centers.ravel().tolist(), self.radii.tolist())

    def surface(self, path=None, **options):
        """The boundary of the union of the spheres as a closed, manifold triangle mesh with outward normals
        (``mss surface``): CGAL's union of balls, subdivided until its volume is within *tolerance* of the
        union's exact volume (and, with *maxEdge*, no edge is longer).

        :param path: also write it there: .stl (binary), .obj or .ply (binary), atomically
        :param options: tolerance (default 0.002), maxEdge (world units, default 0: no bound), maxTriangles
            (default 20,000,000: refused beyond)
        :return: :class:`ClumpSurface`
        """
        o, = split('MssResult.surface', options, ('tolerance', 'maxEdge', 'maxTriangles'))
        d = _mss.unionSurface(self.centers.ravel().tolist(), self.radii.tolist(), o)
        s = ClumpSurface(np.frombuffer(d['vertices'], dtype=np.float64).reshape(-1, 3).copy(),
                         np.frombuffer(d['triangles'], dtype=np.int32).reshape(-1, 3).copy(),
                         {k: d[k] for k in ('subdivisions', 'volume', 'unionVolume', 'longestEdge', 'smallestAngle')})
        if path is not None:
            s.save(path)
        return s

    def timeStep(self, density, young):
        """The critical time step these spheres allow as YADE's ``PWaveTimeStep`` computes it for a clump's
        members: the smallest radius times sqrt(density / young) (a linear contact: sqrt(m / k) ~ r sqrt(rho / E)).

        :param float density: the material's density (mass per world unit cubed)
        :param float young: its Young's modulus (YADE's ``young``)
        :return: the time step (seconds, in the units of *density* and *young*)
        """
        density, young = (number('MssResult.timeStep', n, v) for n, v in (('density', density), ('young', young)))
        if density <= 0 or young <= 0:
            raise ValueError('MssResult.timeStep: density and young must be > 0, got %r and %r' % (density, young))
        return float(self.radii.min()) * float(np.sqrt(density / young))

    def boundingRadius(self, center=None):
        """Radius of the smallest ball about a centre holding every sphere.

        :param center: the centre, 3 numbers (default: the union's centre of mass)
        """
        c = self.unionMass().centroid if center is None else vector3('MssResult.boundingRadius', 'center', center)
        return float(np.max(np.linalg.norm(self.centers - c, axis=1) + self.radii))

    def preview(self, path, grain=None, **kw):
        """Draws these spheres against the grain (default: the one they were generated from) into a PNG; see
        ``mss preview`` (three views, a section, n, D and the largest protrusion).

        :param path: the PNG to write
        :param grain: the grain (a mesh or voxel file, an array, (vertices, triangles)); default: the source
        :param kw: ``mss preview``'s options (resolution, voxelSize, origin, label, title)
        :return: the comparison row (dice, protrusion, ...)
        """
        from ..pictures import preview  # a door to the layer above: drawing is not the result's business
        g = self.grain if grain is None else grain
        if g is None:
            raise ValueError('MssResult.preview: give the grain (this result does not know what it was made from)')
        return preview(g, self, path, title=kw.pop('title', self.source or None), **kw)

    def export(self, path, format=None, **options):
        """Writes these spheres as another DEM code's template, with the grain's exact mass, centre and inertia,
        as ``mss export`` does (:func:`yade_mss.exports.exportTemplate`).

        :param path: the file to write
        :param format: 'liggghts' (the default: an input-script file with ``fix particletemplate/multisphere``)
        :param options: density, frame ('principal' or 'generated'), templateType, atomType
        """
        from ..exports import exportTemplate  # a door to the layer above, as preview
        o, = split('MssResult.export', options, ('density', 'frame', 'templateType', 'atomType'))
        exportTemplate(self, path, format, **o)

    def save(self, path, compress=True):
        """Writes the result by extension: ``.npz`` (everything, for :meth:`load`), or the sphere files of the
        command line: ``.csv`` (x,y,z,r), ``.txt`` (YADE text clump, ``ymport.textClumps``), ``.vtk`` (ParaView),
        or the templates that take no density, with the grain's mass properties: ``.clu`` (Kratos) and ``.p3dat``
        (PFC), as :meth:`export` writes them. Written atomically.

        :param path: the file to write
        :param bool compress: ``.npz``: compressed
        """
        compress = flag('MssResult.save', 'compress', compress)
        path = os.fspath(path)
        if os.path.isdir(path) or path.endswith(os.sep):
            raise ValueError('MssResult.save: %s is a folder: give a file name in it (clump.csv, clump.npz, ...)'
                             % path)
        ext = os.path.splitext(path)[1].lower()
        if ext in ('.csv', '.txt', '.vtk'):
            _mss.writeSpheres(self.centers.ravel().tolist(), self.radii.tolist(), path)
            return
        if ext in TEMPLATE_EXTENSIONS:  # no density in these: the material's applies
            self.export(path, format=TEMPLATE_EXTENSIONS[ext])
            return
        if ext != '.npz':
            raise ValueError("MssResult.save: %s: unknown extension '%s' (expected .npz, .csv, .txt or .vtk, or a "
                             "template: .clu or .p3dat)" % (path, ext))
        atomicWrite(path, lambda tmp: self._npz(tmp, compress), 'MssResult.save')

    def _sphereFile(self, ext):
        """The bytes :meth:`save` writes to a sphere file of extension *ext* (.csv, .txt, .vtk)."""
        # the arrays themselves (the core reads their buffers), not lists of their numbers made and read back
        return _mss.formatSpheres(np.ascontiguousarray(self.centers, dtype=np.float64).ravel(),
                                  np.ascontiguousarray(self.radii, dtype=np.float64), 'spheres' + ext)

    def _npz(self, file, compress=False):
        """Writes the .npz that :meth:`load` reads to *file* (a path or a binary file object)."""
        arrays = self._arrays()
        if compress:
            np.savez_compressed(file, **arrays)
            return
        data = storedNpz(arrays)
        if isinstance(file, (str, bytes, os.PathLike)):
            with open(file, 'wb') as f:
                f.write(data)
        else:
            file.write(data)

    def _npzBytes(self):
        """The bytes of the (uncompressed) .npz that :meth:`load` reads."""
        return storedNpz(self._arrays())

    def _arrays(self):
        meta = {'metrics': self.metrics, 'grid': self.grid, 'source': self.source,
                'targetMass': self.targetMass._toDict() if self.targetMass is not None else None, 'version': 1}
        return {'centers': self.centers, 'radii': self.radii, 'meta': np.array(json.dumps(meta))}

    @staticmethod
    def load(path):
        """Reads a result written by :meth:`save` (.npz).

        :param path: the .npz file (a sphere file is refused: :func:`readSpheres` reads those)
        :return: :class:`MssResult`
        """
        ext = os.path.splitext(os.fspath(path))[1].lower()
        if ext in ('.csv', '.txt', '.vtk'):
            raise ValueError('MssResult.load: %s: a sphere file, not a saved result (.npz): read it with '
                             'readSpheres' % (path,))
        try:
            _checkArchive(os.fspath(path))
            with np.load(str(path), allow_pickle=False) as z:
                meta = json.loads(str(z['meta']))
                centers, radii = z['centers'], z['radii']
                if centers.ndim != 2 or centers.shape[1:] != (3,) or radii.shape != (len(centers),):
                    raise ValueError('centres must be (n, 3) and radii (n,), got %s and %s'
                                     % (centers.shape, radii.shape))
                if not isinstance(meta, dict):
                    raise ValueError('its meta data is not a dict')
                r = MssResult(centers, radii, meta.get('metrics'), meta.get('grid'), None, meta.get('source', ''))
                if meta.get('targetMass'):
                    r.targetMass = MassProperties._fromDict(meta['targetMass'])
        except (OSError, KeyError, ValueError, TypeError, AttributeError, EOFError, zipfile.BadZipFile, zlib.error,
                NotImplementedError, struct.error) as e:
            # zlib.error: a damaged deflate stream shows only while an array is expanded; NotImplementedError: the
            # zip reader's answer to a damaged version field
            raise ValueError('MssResult.load: %s: not a saved result (%s)' % (path, e))
        return r


MAX_ARCHIVE_BYTES = 1 << 30  # a result of a million spheres takes 32 MB


_ZIP_DATE = (1 << 5) | 1  # 1980-01-01 (DOS date), the time 00:00: an archive's bytes are its arrays' alone


def storedNpz(arrays):
    """The bytes of an uncompressed .npz of *arrays* ({name: array}, names of letters), as ``np.savez`` writes
    and ``np.load`` reads: a zip (stored members, no zip64: members under 4 GB) of one .npy (version 1.0) an
    array. A batch writes one a grain: np.savez, through ZipFile, took three times as long."""
    out, central = [], []
    at = 0
    for name, a in arrays.items():
        a = np.asarray(a)
        if a.dtype.hasobject:  # its bytes would be pointers: np.save pickles these, a result has none
            raise ValueError('storedNpz: %s holds Python objects (%s): only numbers and text' % (name, a.dtype))
        header = repr({'descr': np.lib.format.dtype_to_descr(a.dtype), 'fortran_order': False,
                       'shape': a.shape}).encode('latin1')
        pad = -(10 + len(header) + 1) % 64  # the data starts on 64 bytes, as numpy aligns it
        body = b'\x93NUMPY\x01\x00' + struct.pack('<H', len(header) + pad + 1) + header + b' ' * pad + b'\n'
        body += np.ascontiguousarray(a).tobytes()
        if len(body) >= 1 << 32:
            raise ValueError('storedNpz: %s is 4 GB or more: save it compressed' % name)
        member = (name + '.npy').encode('ascii')
        crc = zlib.crc32(body)
        local = struct.pack('<4s2B4HL2L2H', b'PK\x03\x04', 20, 0, 0, zipfile.ZIP_STORED, 0, _ZIP_DATE, crc,
                            len(body), len(body), len(member), 0)
        central.append(struct.pack('<4s4B4HL2L5H2L', b'PK\x01\x02', 20, 3, 20, 0, 0, zipfile.ZIP_STORED, 0,
                                   _ZIP_DATE, crc, len(body), len(body), len(member), 0, 0, 0, 0, 0o644 << 16, at)
                       + member)
        out += [local, member, body]
        at += len(local) + len(member) + len(body)
    directory = b''.join(central)
    if at >= 1 << 32:
        raise ValueError('storedNpz: the arrays are 4 GB or more: save them compressed')
    end = struct.pack('<4s4H2LH', b'PK\x05\x06', 0, 0, len(central), len(central), len(directory), at, 0)
    return b''.join(out) + directory + end


def _checkArchive(path):
    """A saved result's .npz, checked before anything is expanded: a zip of the arrays a result has, whose
    sizes once expanded stay under MAX_ARCHIVE_BYTES (a 3 MB archive expanded to 2.8 GB)."""
    with zipfile.ZipFile(path) as z:
        total = 0
        for info in z.infolist():
            if info.filename not in ('centers.npy', 'radii.npy', 'meta.npy'):
                raise ValueError("unexpected member '%s'" % info.filename)
            if (info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED) or info.flag_bits & 0x1
                    or info.extract_version > zipfile.MAX_EXTRACT_VERSION):
                # what save() writes; other methods and encryption would fail later with other exceptions
                raise ValueError("member '%s' is encrypted, compressed by method %d or needs zip version %.1f"
                                 % (info.filename, info.compress_type, info.extract_version / 10))
            total += info.file_size
        if total > MAX_ARCHIVE_BYTES:
            raise ValueError('its arrays would take %d bytes expanded (at most %d)' % (total, MAX_ARCHIVE_BYTES))


def readSpheres(path, clumpId=None):
    """Reads a sphere file (CLUMP's ``x,y,z,r`` CSV, a YADE text clump ``x y z r id``, our .csv/.txt) as an
    :class:`MssResult` without a target (use ``mass='union'`` with it).

    :param path: the sphere file
    :param int clumpId: of a YADE text file holding several clumps, the one to read; such a file is refused
        without it (clumps are never merged silently). :func:`readClumps` reads them all, as clumps.
    """
    clump = -1 if clumpId is None else integer('readSpheres', 'clumpId', clumpId, 0, INT64_MAX)
    if not isinstance(path, (str, bytes, os.PathLike)):
        raise TypeError('spheres must be a sphere file (its path) or an MssResult (MssResult(centers, radii) of '
                        'arrays), got %s' % type(path).__name__)
    c, r = _mss.readSpheres(os.fspath(path), clump)
    return MssResult(c, r, source=os.path.basename(os.fspath(path)))


class ClumpSurface(object):
    """A clump's surface (:meth:`MssResult.surface`): ``vertices`` (n, 3) in world units, ``triangles`` (m, 3)
    vertex indices, counter-clockwise seen from outside; ``volume`` (the mesh's), ``unionVolume`` (the spheres'
    union's, exact), ``subdivisions``, ``longestEdge`` and ``smallestAngle`` (degrees)."""

    def __init__(self, vertices, triangles, report):
        self.vertices, self.triangles = vertices, triangles
        for k, v in report.items():
            setattr(self, k, v)

    def save(self, path):
        """Writes the mesh by extension: .stl (binary), .obj or .ply (binary), atomically."""
        _mss.writeMesh(self.vertices.ravel().tolist(), self.triangles.ravel().tolist(), os.fspath(path))

    def __repr__(self):
        return 'ClumpSurface(%d vertices, %d triangles, volume %.6g of the union\'s %.6g)' % (
            len(self.vertices), len(self.triangles), self.volume, self.unionVolume)
