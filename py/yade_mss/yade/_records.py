"""The records that let :func:`restoreClumpProperties` give a clump its exact mass properties back, numpy only.

A clump's record is carried by the clump body itself, as the label of a material of its own (a clump body of
YADE has none, and nothing in YADE reads one: contacts are its members'). So YADE saves it with the body
(``O.save``, ``saveTmp``), and it goes when the clump goes (``erase``, ``O.bodies.clear()``, ``O.reset()``): it
can never be found by another clump that reuses the id. (``O.tags`` was the first home: YADE scans every tag's
text at each access, so a record a clump made building n clumps cost O(n^2).)

It holds the clump's plan at unit density and a fingerprint of its members (ids, radii, positions), in the
frame F of its second member (position x0 of the first, rotation F = R1 of the second; one member: its own). The
members turn with the clump, so the record holds wherever the clump goes; and member 1 is never turned by
yade-mss (member 0 wears the orientation V* of its load tensor's axes, set again at each restore), so a
restore of an unchanged clump leaves its record as it was: nothing is written.

A breakable clump (:func:`yade_mss.mssSplit`) carries its grain too, after the record: ``|g:`` and its mesh
(vertices in the record's frame, float64, and triangles, int32: zlib, base64), so that O.save keeps what a
split needs and a clump that goes takes its grain with it.

Layout: float64, little endian, base64 after ``mss3:``: [3, n, volume, centroid (3), inertia (9), member 0's load
tensor (9), ids (n), radii (n), positions (3n), masses for the sums (n)]. ``mss2:`` records (frame of member 0,
rewritten at each restore) are not read.
"""

import base64
import zlib

import numpy as np

PREFIX = 'mss3:'
OLDER = 'mss2:'  # the frame of member 0 (not read: the clump's record is dropped with a warning)
OLD_TAG = 'mss.clump.'  # O.tags, one a clump, JSON: yade-mss before records had fingerprints (not read)
_HEAD = 3 + 3 + 9 + 9


def quaternionMatrices(q):
    """Rotation matrices (k, 3, 3) of unit quaternions (k, 4) given as (x, y, z, w), as minieigen indexes them."""
    q = np.asarray(q, dtype=float).reshape(-1, 4)
    x, y, z, w = q.T
    return np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                     2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                     2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], axis=1).reshape(-1, 3, 3)


def recordParts(x, radii, volume, C, I, m, V, j, F):
    """What the records of k clumps hold besides the member ids, as bytes before and after them: lists of per-clump
    arrays *x* (n, 3), *radii*, *m*; stacked *volume* (k), *C* (k, 3), *I*, *V* (k, 3, 3), *j* (k, 3), at unit
    density, and the frames *F* (k, 3, 3): member 1's rotation matrix (one member: member 0's, V^T). All of it is
    relative to member 0 and the frame, so clumps placed alike (the same turn and scale) share it.
    :return: list of k (head, tail) byte strings"""
    k = len(x)
    x0 = np.array([xi[0] for xi in x]).reshape(k, 3)
    Ft = np.transpose(F, (0, 2, 1))  # stacked matmul: einsum's overhead was most of a single clump's cost
    crel = (Ft @ (C - x0)[:, :, None])[:, :, 0]
    Irel = Ft @ I @ F
    J = (V * np.asarray(j)[:, None, :]) @ np.transpose(V, (0, 2, 1))  # V diag(j) V^T
    Jrel = Ft @ J @ F
    out = []
    for i in range(k):
        rel = (x[i] - x0[i]).dot(F[i])
        head = np.concatenate([[3.0, len(radii[i]), volume[i]], crel[i], Irel[i].ravel(), Jrel[i].ravel()])
        tail = np.concatenate([radii[i], rel.ravel(), m[i]])
        out.append((head.astype('<f8').tobytes(), tail.astype('<f8').tobytes()))
    return out


def encodeParts(ids, parts):
    """Records from their member *ids* (a list per clump) and :func:`recordParts`. :return: list of strings"""
    return [PREFIX + base64.b64encode(head + np.asarray(i, dtype='<f8').tobytes() + tail).decode('ascii')
            for i, (head, tail) in zip(ids, parts)]


def encodeMany(ids, x, radii, volume, C, I, m, V, j, F):
    """Records of k clumps just given their loads: member *ids* (a list per clump), the rest as
    :func:`recordParts` takes it. :return: list of k strings"""
    return encodeParts(ids, recordParts(x, radii, volume, C, I, m, V, j, F))


class Record(object):
    """A decoded record: volume, centroid, inertia, J (frame F, unit density), ids, radii, rel (n, 3), m.
    Raises ValueError for a text that is not one."""

    def __init__(self, text):
        try:
            a = np.frombuffer(base64.b64decode(text[len(PREFIX):], validate=True), dtype='<f8')
        except (ValueError, TypeError):
            raise ValueError('not a record')
        n = int(a[1]) if a.size >= 2 and np.isfinite(a[1]) and 1 <= a[1] <= a.size else -1
        if n < 1 or a[0] != 3 or a.size != _HEAD + 6 * n or not np.all(np.isfinite(a)):
            raise ValueError('not a record')
        self.volume = float(a[2])
        self.centroid, self.inertia, self.J = a[3:6], a[6:15].reshape(3, 3), a[15:24].reshape(3, 3)
        k = _HEAD
        self.ids = a[k:k + n].astype(np.int64).tolist()
        self.radii = a[k + n:k + 2 * n]
        self.rel = a[k + 2 * n:k + 5 * n].reshape(n, 3)
        self.m = a[k + 5 * n:k + 6 * n]


GRAIN = '|g:'


def encodeGrain(vertices, triangles):
    """The ``|g:`` part of a label: a mesh, *vertices* (n, 3) in the record's frame and *triangles* (m, 3)."""
    v = np.ascontiguousarray(vertices, dtype='<f8').reshape(-1, 3)
    t = np.ascontiguousarray(triangles, dtype='<i4').reshape(-1, 3)
    head = np.array([len(v), len(t)], dtype='<i8').tobytes()
    return GRAIN + base64.b64encode(zlib.compress(head + v.tobytes() + t.tobytes(), 1)).decode('ascii')


def grainOf(text):
    """The mesh a label carries after its record: (vertices (n, 3), triangles (m, 3)) in the record's frame,
    None (none), or False (not readable)."""
    k = text.find(GRAIN)
    if k < 0:
        return None
    try:
        raw = zlib.decompress(base64.b64decode(text[k + len(GRAIN):], validate=True))
        nv, nt = (int(x) for x in np.frombuffer(raw[:16], dtype='<i8'))
        if nv < 3 or nt < 4 or len(raw) != 16 + 24 * nv + 12 * nt:
            return False
        v = np.frombuffer(raw, dtype='<f8', count=3 * nv, offset=16).reshape(nv, 3)
        t = np.frombuffer(raw, dtype='<i4', count=3 * nt, offset=16 + 24 * nv).reshape(nt, 3)
    except (ValueError, TypeError, zlib.error):
        return False
    if not (np.all(np.isfinite(v)) and t.min() >= 0 and t.max() < nv):
        return False
    return v, t


def labelOf(body):
    mat = body.material
    return mat.label if mat is not None else ''


def recordOf(body, text=None):
    """The record a clump body carries (its label *text*, if already read): a :class:`Record`, None (none: a
    clump made otherwise), or False (not readable: damaged)."""
    text = labelOf(body) if text is None else text
    if text.startswith(OLDER):
        return False
    if not text.startswith(PREFIX):
        return None
    k = text.find(GRAIN)
    try:
        return Record(text if k < 0 else text[:k])
    except ValueError:
        return False


def attach(body, text, Material, grain=None):
    """Gives the clump body its record (*Material*: YADE's base material class) and its grain (an
    :func:`encodeGrain` text; None: the one it carries, if any)."""
    if grain is None:
        old = labelOf(body)
        k = old.find(GRAIN) if old.startswith(PREFIX) else -1
        grain = old[k:] if k >= 0 else ''
    body.material = Material(label=text + grain, density=0)


def drop(body):
    body.material = None  # as YADE's own clumps: no material


def scaled(rec, s):
    """Record *rec* of a clump grown by *s* about its centre (``utils.growParticles(s)`` scales the members' radii
    and their offsets from the clump's centre): lengths times s, volumes s^3, second moments s^5."""
    out = Record.__new__(Record)
    out.volume, out.centroid, out.inertia, out.J = rec.volume * s ** 3, rec.centroid * s, rec.inertia * s ** 5, \
        rec.J * s ** 5
    out.ids, out.radii, out.rel, out.m = list(rec.ids), rec.radii * s, rec.rel * s, rec.m * s ** 3
    return out


def scaleOf(rec, ids, radii, x, F):
    """The factor s by which the clump found (as :func:`matchMembers` takes it) is its record's clump grown about
    its centre, every member's radius and offset times s (YADE's ``utils.growParticles``); None where it is not."""
    if rec.ids != ids or not rec.radii[0] > 0:
        return None
    s = float(radii[0] / rec.radii[0])
    size = float(np.ptp(x, axis=0).max() + 2 * radii.max())
    if s > 0 and np.abs(rec.radii * s - radii).max() <= 1e-12 * radii.max() \
            and np.abs((x - x[0]).dot(F) - s * rec.rel).max() <= 1e-9 * size:
        return s
    return None


def matchMembers(rec, ids, radii, x, F):
    """How the members found (ids, radii, positions (n, 3), the record's frame now: member 1's rotation, or
    member 0's alone) match record *rec*: 'same' (ids, radii and positions in that frame as recorded), 'scaled'
    (all of them grown alike about the centre: :func:`scaleOf`), 'changed' (some recorded members left or others
    joined, the rest where they were: their distances), or None (another clump)."""
    size = float(np.ptp(x, axis=0).max() + 2 * radii.max())
    tol = 1e-9 * size
    if rec.ids == ids:
        if (np.abs(rec.radii - radii).max() <= 1e-12 * radii.max()
                and np.abs((x - x[0]).dot(F) - rec.rel).max() <= tol):
            return 'same'
        return 'scaled' if scaleOf(rec, ids, radii, x, F) is not None else None
    where = {i: k for k, i in enumerate(rec.ids)}
    common = [(k, where[i]) for k, i in enumerate(ids) if i in where]
    if not common:
        return None
    a = np.array([k for k, _ in common])
    b = np.array([k for _, k in common])
    if np.abs(rec.radii[b] - radii[a]).max() > 1e-12 * radii.max():
        return None
    da = np.linalg.norm(x[a][:, None] - x[a][None], axis=2)
    db = np.linalg.norm(rec.rel[b][:, None] - rec.rel[b][None], axis=2)
    return 'changed' if np.abs(da - db).max() <= tol else None
