"""What a batch wrote and what it says: each grain's problems (the reasons it deserves a look), the assembly's
critical time step and the grains that set it, and the files: ``grains.csv``, ``assembly.txt`` (for
``readClumps`` and ``ymport.textClumps``), ``assembly.vtk`` (ParaView) and ``report.html``, worst grain first."""

import csv
import html
import math
import os
import urllib.parse

import numpy as np

from .. import _mss
from ..base import atomicWrite
from ..grains import NEARBY_GAP, SPECK_VOXELS
from ..pictures import preview

COLUMNS = ['label', 'file', 'status', 'problems', 'voxels', 'spheres', 'dice', 'eta', 'protrusion', 'r_min',
           'r_min_voxels', 'thickness_voxels', 'time_step', 'contacts_ct', 'contacts_kept', 'contacts_not_generated',
           'contacts_lost_why', 'contacts_assembly', 'contact_spheres', 'seconds', 'touches_border', 'message']
DICE_FLAG = 0.1  # D above this (or above a --dice target) flags a grain
THIN_VOXELS = 2.5  # a largest inscribed radius under this (grains at most 4 voxels thick): thin, hard to fill
STEP_MARGIN = 1.1  # grains whose time step is within 10% of the least "set" the assembly's
MAX_PREVIEWS = 12
# the order of the report: what needs a look first
_SEVERITY = {'failed': 0, 'flagged': 1, 'too small': 2, 'border': 3, 'ok': 4, 'skipped': 5}


def _number(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return None


KEPT_GAP = 0.5  # voxels: a scan's contact is kept when the two clumps' spheres come this close




def packed(clumps):
    """(spheres, offsets) of a batch's clumps in their order: every sphere as a row x y z r, and where each
    clump's rows start (one more: the end). A batch with an output folder packs them as they come
    (:class:`yade_mss.specimens._batch.PackedClumps`)."""
    parts = [np.column_stack([c.centers, c.radii]) for c in clumps.values()]  # results in memory: few
    counts = np.array([len(p) for p in parts], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum(counts)])
    return (np.concatenate(parts) if parts else np.zeros((0, 4))), offsets


def _gaps(spheres, offsets, i, j):
    """The least gap between the sphere sets of clumps i[n] and j[n] (packed: :func:`packed`), for every n,
    (negative: they overlap by that much): the core's, every sphere pair of each (numpy's batched products of
    padded pairs took ten times as long)."""
    def raw(a, dtype):
        return np.ascontiguousarray(a, dtype=dtype).tobytes()
    # the spheres passed as they are (read in place), the rest as bytes
    return np.frombuffer(_mss.clumpGaps(np.ascontiguousarray(spheres, dtype=np.float64).reshape(-1, 4),
                                        raw(offsets, np.int64), raw(i, np.int64), raw(j, np.int64)),
                         dtype=np.float64)


def _gap(r1, r2):
    """The least gap between two sphere sets (negative: they overlap by that much)."""
    d = np.linalg.norm(r1.centers[:, None, :] - r2.centers[None, :, :], axis=-1)
    return float((d - r1.radii[:, None] - r2.radii[None, :]).min())


def _assemblyPairs(spheres, offsets, tolerance):
    """The pairs (i, j), i < j, of clumps (packed: :func:`packed`) that may come within *tolerance* (world
    units) of each other, and their gaps: the clumps' bounding balls narrow the pairs (a k-d tree), the spheres
    give the gaps (those over *tolerance* included: the caller keeps what it needs)."""
    from scipy.spatial import cKDTree
    n = len(offsets) - 1
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64), np.zeros(0)
    start = offsets[:-1]
    lo = np.minimum.reduceat(spheres[:, :3], start)
    hi = np.maximum.reduceat(spheres[:, :3], start)
    centre = 0.5 * (lo + hi)
    # each sphere's reach from its clump's centre, a chunk of spheres at a time (10^6 spheres and more)
    far = np.empty(len(spheres))
    for x in range(0, len(spheres), CHUNK):
        rows = np.arange(x, min(x + CHUNK, len(spheres)))
        owner = np.searchsorted(offsets, rows, side='right') - 1
        far[rows] = np.linalg.norm(spheres[rows, :3] - centre[owner], axis=1) + spheres[rows, 3]
    reach = np.maximum.reduceat(far, start)
    del far
    # the candidates (centres within twice the largest reach) a slab of clumps at a time along x: all at once,
    # the pass added 210 MB to a batch's peak at 10^5 clumps (3.4 times the pairs kept). Clumps in x order; a
    # slab's own are the ones at positions s0 .. s1 - 1, its tree holds those and the ones up to r beyond its
    # last; a pair is the slab's of its first member, so each is found once.
    r = 2 * reach.max() + tolerance
    order = np.argsort(centre[:, 0], kind='stable')
    xs = centre[order, 0]
    keep = []
    for s0 in range(0, n, SLAB_CLUMPS):
        s1 = min(n, s0 + SLAB_CLUMPS)
        e = int(np.searchsorted(xs, xs[s1 - 1] + r, side='right'))
        local = cKDTree(centre[order[s0:e]]).query_pairs(r, output_type='ndarray')
        local = local[local.min(axis=1) < s1 - s0] + s0
        a, b = order[local[:, 0]], order[local[:, 1]]
        i, j = np.minimum(a, b), np.maximum(a, b)
        near = np.linalg.norm(centre[i] - centre[j], axis=1) <= reach[i] + reach[j] + tolerance
        keep.append(np.column_stack([i[near], j[near]]))
    pairs = np.concatenate(keep) if keep else np.zeros((0, 2), dtype=np.int64)
    return pairs, _gaps(spheres, offsets, pairs[:, 0], pairs[:, 1])


CHUNK = 1 << 18  # rows of the arrays above handled at once: their temporaries stay a few MB
SLAB_CLUMPS = 1 << 13  # clumps a slab of _assemblyPairs' candidates: a few tens of MB of them


def keptContacts(b, found, h):
    """Each row's ``contacts_ct`` (the scan's contacts of the grain: grains within the contact gap of it),
    ``contacts_kept`` (those whose two clumps come within KEPT_GAP voxels) and ``contacts_assembly`` (the clumps
    within the same contact gap of its clump, scan contacts or not), and the batch's ``contacts``: pairs in the
    scan, between two generated grains, kept, in the assembly; the coordination numbers (both counted with the
    same tolerance); the largest overlap of a kept pair (voxels); where the scan shows no pair, the gaps between
    the grains near each other (``nearby``). Nothing without contacts (a folder of grains, or contacts off).
    *found*: :class:`yade_mss.grains.ScanContacts` (columns: 10^6 contacts of 10^5 grains pass as arrays)."""
    b.contacts, b.scanContacts = None, found
    if found is None:
        return
    tolerance = float(getattr(found, 'gap', 0.0))
    keys = list(b.clumps)
    n = len(keys)
    spheres, offsets = b.packed()
    labels = np.array([int(b.rows[k]['label']) for k in keys], dtype=np.int64)
    order = np.argsort(labels)

    def where(lab):  # each label's place among the generated grains, -1 where it was not generated
        if not n:
            return np.full(len(lab), -1)
        at = np.minimum(np.searchsorted(labels[order], lab), n - 1)
        return np.where(labels[order][at] == lab, order[at], -1)
    ia, ib = where(found.a), where(found.b)
    ends, many = np.unique(np.concatenate([found.a, found.b]), return_counts=True)
    ct = dict(zip(ends.tolist(), many.tolist()))
    # a contact with a grain not generated (skipped, failed) is not lost: counted apart, for the generated one
    one = (ia >= 0) != (ib >= 0)
    other = np.bincount(np.maximum(ia, ib)[one], minlength=n)
    both = np.flatnonzero((ia >= 0) & (ib >= 0))
    # the clumps' pairs within the larger of the two tolerances, each with its gap, once: the scan's pairs
    # among them are kept or not by their gap, those beyond it are not kept
    pairs, gaps = _assemblyPairs(spheres, offsets, max(tolerance, KEPT_GAP) * h)
    code = pairs[:, 0] * max(1, n) + pairs[:, 1]
    order = np.argsort(code)
    code, gaps = code[order], gaps[order]
    want = np.minimum(ia[both], ib[both]) * max(1, n) + np.maximum(ia[both], ib[both])
    at = np.minimum(np.searchsorted(code, want), max(0, len(code) - 1))
    g = np.where(code[at] == want, gaps[at], np.inf) / h if len(code) else np.full(len(want), np.inf)
    keep = g <= KEPT_GAP
    kept = np.bincount(np.concatenate([ia[both[keep]], ib[both[keep]]]), minlength=n)
    overlap = max(0.0, float((-g[keep]).max())) if keep.any() else 0.0
    why, lost = {}, {}
    for c in both[~keep]:  # lost: why, as far as the scan tells
        reason = lostReason(found[c], b.rows[keys[ia[c]]], b.rows[keys[ib[c]]])
        lost[reason] = lost.get(reason, 0) + 1
        for x in (ia[c], ib[c]):
            why.setdefault(int(x), {})[reason] = why.setdefault(int(x), {}).get(reason, 0) + 1
    assembly = pairs[order][gaps <= tolerance * h]
    near = np.bincount(assembly.ravel(), minlength=n)
    at = {k: x for x, k in enumerate(keys)}
    for k, row in b.rows.items():
        lab = row['label']
        if lab != '':
            x = at.get(k)
            row['contacts_ct'] = ct.get(lab, 0)
            row['contacts_kept'] = int(kept[x]) if x is not None else ''
            row['contacts_not_generated'] = int(other[x]) if x is not None else ''
            row['contacts_assembly'] = int(near[x]) if x is not None else ''
            row['contacts_lost_why'] = reasonsText(why.get(x, {})) if x is not None else ''
    m = max(1, n)
    b.contacts = {'pairs': len(found), 'between': len(both), 'kept': int(keep.sum()), 'overlap': overlap,
                  'gap': tolerance, 'assembly': len(assembly), 'coordinationScan': 2.0 * len(both) / m,
                  'coordinationAssembly': 2.0 * len(assembly) / m, 'nearby': getattr(found, 'nearby', None),
                  'lost': lost}


LOST_BORDER = 'a grain cut by the border'
LOST_GAP = 'apart in the scan (a gap over a voxel)'
LOST_REACH = 'not reached by the clumps'


def lostReason(c, rowA, rowB):
    """Why a contact of the scan is not kept in the assembly: one of its grains ends where the scan does (its
    clump is cut there, and its contact balls with it), or the grains are apart in the scan (a gap over a
    voxel: the balls meet at the middle, the clumps' bound leaves them short), or else the clumps do not
    reach each other."""
    if int(rowA.get('touches_border') or 0) or int(rowB.get('touches_border') or 0):
        return LOST_BORDER
    if float(c.get('gap', 0.0)) > 1.0:
        return LOST_GAP
    return LOST_REACH


def reasonsText(counts):
    """'3 with a grain cut by the border, 1 apart in the scan (2 voxels)', largest first."""
    return ', '.join('%d %s%s' % (n, 'with ' if r == LOST_BORDER else '', r)
                     for r, n in sorted(counts.items(), key=lambda kv: -kv[1]))


def gapsText(c):
    """Why a scan shows no contacts: the tolerance, and the gaps between the grains near each other."""
    text = 'No two grains of the scan come within %g voxel%s of each other (the contact gap, --contact-gap).' % (
        c['gap'], '' if c['gap'] == 1 else 's')
    near = c.get('nearby')
    if near is None:
        return text
    if not near:
        return text + ' None comes within %g voxels either: the grains lie apart.' % NEARBY_GAP
    edges = [x for x in (1, 1.5, 2, 2.5, 3) if x > c['gap']]
    parts, lo = [], c['gap']
    for e in edges:
        k = sum(1 for g in near if lo < g <= e + 1e-9)
        if k:
            parts.append('%d within (%g, %g]' % (k, lo, e))
        lo = e
    return text + (' %d pair%s of grains lie within %g voxels: %s (least gap %.3g voxels); a larger '
                   '--contact-gap would count them.' % (len(near), '' if len(near) == 1 else 's', NEARBY_GAP,
                                                       ', '.join(parts), min(near)))


def flagLine(options):
    """The D above which a grain is flagged: the target asked (dice), else DICE_FLAG."""
    target = options.get('dice') or 0.0
    return target if target > 0 else DICE_FLAG


def annotate(b, options, density, young):
    """Fills each row's ``time_step`` and ``problems``, and the batch's ``timeStep``, ``setBy`` and ``ranked`` (keys,
    worst first)."""
    scale = math.sqrt(density / young)  # PWaveTimeStep of a sphere: r sqrt(rho / E)
    steps = {}
    for k, row in b.rows.items():
        r = _number(row.get('r_min'))
        if row['status'] == 'ok' and r is None and k in b.clumps:  # a row of an earlier layout
            r = float(b.clumps[k].radii.min())
            row['r_min'] = r
        row['time_step'] = r * scale if row['status'] == 'ok' and r is not None else ''
        if row['time_step'] != '':
            steps[k] = row['time_step']
    b.timeStep = min(steps.values()) if steps else None
    b.setBy = sorted((k for k, t in steps.items() if t <= STEP_MARGIN * b.timeStep), key=lambda k: steps[k])
    target = options.get('dice') or 0.0
    flagAt = b.flagAt = flagLine(options)
    asked = options.get('nSpheres')
    kinds = {}
    for k, row in b.rows.items():
        reasons, kind = [], row['status']
        if kind == 'failed':
            reasons.append('failed')
        elif kind == 'skipped':
            if 'too small' in row.get('message', ''):
                reasons.append('too small for the radius bound')
                kind = 'too small'
        else:
            d, thick = _number(row['dice']), _number(row.get('thickness_voxels'))
            if d is not None and d > flagAt:
                reasons.append('D %.3g above %s%.3g' % (d, 'the target ' if target > 0 else '', flagAt))
            if thick is not None and thick < THIN_VOXELS:
                reasons.append('thin (largest inscribed radius %.2g voxels)' % thick)
            # fewer spheres than asked is a problem only where D is poor too (a ball needs one)
            if asked and int(row['spheres']) < asked and d is not None and d > flagAt / 2:
                reasons.append('%s of the %d spheres asked' % (row['spheres'], asked))
            ct, kept = _number(row.get('contacts_ct')), _number(row.get('contacts_kept'))
            other = _number(row.get('contacts_not_generated')) or 0
            if ct is not None and kept is not None and kept + other < ct:
                whyLost = row.get('contacts_lost_why') or ''
                reasons.append('%d of its %d contacts in the scan lost%s%s' % (
                    ct - other - kept, ct, ': %s' % whyLost if whyLost else '',
                    ' (%d more with grains not generated)' % other if other else ''))
            if k in b.setBy:
                reasons.append('sets the time step (smallest radius %.3g voxels)' % _number(row['r_min_voxels'])
                               if _number(row.get('r_min_voxels')) is not None else 'sets the time step')
            kind = 'flagged' if reasons else 'ok'
            if int(row.get('touches_border') or 0):
                reasons.append('cut by the border')
                kind = 'border' if kind == 'ok' else kind
        row['problems'] = '; '.join(reasons)
        kinds[k] = kind
    b.ranked = sorted(b.rows, key=lambda k: (_SEVERITY[kinds[k]], -(_number(b.rows[k]['dice']) or 0.0)))
    b.kinds = kinds


def worthALook(b):
    """The keys to draw: flagged grains worst first (at most MAX_PREVIEWS), or the three of highest D if none."""
    ok = [k for k in b.ranked if k in b.results]
    flagged = [k for k in ok if b.kinds[k] == 'flagged']
    return (flagged or ok[:3])[:MAX_PREVIEWS]


def drawPreviews(outdir, b, tasks):
    """Pictures (as ``mss preview``) of the grains worth a look, into grains/KEY.png; ``b.previewed`` lists them.
    Drawn here, once the batch knows which: every grain's picture cost several times its generation."""
    b.previewed = []
    for k in worthALook(b):
        t = tasks.get(k)
        if t is None:
            continue
        grain = t.crop if t.crop is not None else t.path
        kw = {'voxelSize': t.voxelSize, 'origin': t.origin} if t.crop is not None else {}
        atomicWrite(os.path.join(outdir, 'grains', k + '.png'),
                    lambda p: preview(grain, b.results[k], p, title=k, **kw), 'batch')
        b.previewed.append(k)


def grains(n):
    """'1 grain', '2 grains'."""
    return '%d grain%s' % (n, '' if n == 1 else 's')


def summary(b, total, density, young):
    """The line ``mss batch`` ends with."""
    rows = b.rows.values()
    ok = sum(1 for r in rows if r['status'] == 'ok')
    text = ('batch: %d ok, %d skipped, %d failed of %s in %.2f s (%s generated in this run, %.1f grains/s%s)'
            % (ok, sum(1 for r in rows if r['status'] == 'skipped'), len(b.failed), grains(total), b.seconds,
               grains(b.generated), b.generated / b.seconds if b.seconds > 0 else 0.0,
               '; %s reused from an earlier run' % grains(b.reused) if getattr(b, 'reused', 0) else ''))
    h = getattr(b, 'voxelSize', None)
    if h is not None:
        text += ('\nbatch: voxel edge %g m (--voxel-size, --scale)' % h if getattr(b, 'voxelSizeGiven', False) else
                 '\nbatch: voxel edge 1 (no --voxel-size): lengths, masses and the time step are in voxels, not '
                 'metres; give --voxel-size, the voxel edge in metres, for YADE')
    if b.timeStep is not None:
        text += '\nbatch: time step %.3g s (density %g, young %g), set by %s' % (
            b.timeStep, density, young, ', '.join(b.setBy[:5]) + (' and %d more' % (len(b.setBy) - 5)
                                                                if len(b.setBy) > 5 else ''))
    if getattr(b, 'contacts', None):
        c = b.contacts
        if c['pairs'] == 0:
            text += '\nbatch: contacts: ' + gapsText(c)
        else:
            text += ('\nbatch: contacts: %d pairs of grains within %g voxel%s in the scan, %d between generated '
                     'grains, '
                     '%d of them kept (clumps within %.1f voxel); %d pairs within %g voxel%s in the assembly; '
                     'coordination %.2f in the scan, %.2f in the assembly'
                     % (c['pairs'], c['gap'], _s(c['gap']), c['between'], c['kept'], KEPT_GAP, c['assembly'],
                        c['gap'], _s(c['gap']), c['coordinationScan'], c['coordinationAssembly']))
            if c.get('lost'):
                text += '\nbatch: contacts lost: %s' % reasonsText(c['lost'])
    if b.ranked and b.rows[b.ranked[0]]['problems']:
        k = b.ranked[0]
        text += '\nbatch: worst: %s (%s)' % (k, b.rows[k]['problems'])
    return text


def _s(n):
    """The plural's s: '1 voxel', '2 voxels'."""
    return '' if n == 1 else 's'


def writeOutputs(outdir, b, density, young):
    """grains.csv (label order), assembly.txt, assembly.vtk, contacts.csv (a scan's) and report.html, each
    atomically (the report's pictures are :func:`drawPictures`')."""
    rows = list(b.rows.values())

    def table(p):  # a file name's bytes that are not UTF-8 are written as their escapes, never lost
        with open(p, 'w', newline='', encoding='utf-8', errors='backslashreplace') as f:
            w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction='ignore')
            w.writeheader()
            w.writerows(rows)
    _atomic(os.path.join(outdir, 'grains.csv'), table)
    ids = {k: (b.rows[k]['label'] if b.rows[k]['label'] != '' else i) for i, k in enumerate(b.clumps, 1)}
    _atomic(os.path.join(outdir, 'assembly.txt'), lambda p: _writeAssembly(p, b, ids))
    _atomic(os.path.join(outdir, 'assembly.vtk'), lambda p: writeVtk(p, b, ids))
    if getattr(b, 'scanContacts', None) is not None:
        _atomic(os.path.join(outdir, 'contacts.csv'), lambda p: _writeContacts(p, b.scanContacts))
    _report(outdir, b, density, young)


def _writeAssembly(path, b, ids):
    """assembly.txt: each clump's exact mass properties (a #mss line), then its spheres, a line each; the
    numbers as repr writes them (the shortest text that reads back the same), formatted by the core a chunk of
    clumps at a time."""
    spheres, offsets = b.packed()
    # volume, centroid, then the inertia's xx yy zz xy xz yz, of each clump's row of masses()
    heads = np.ascontiguousarray(b.clumps.masses()[:, [0, 1, 2, 3, 4, 8, 12, 5, 6, 9]], dtype=np.float64)
    cids = np.array([int(ids[k]) for k in b.clumps], dtype=np.int64)
    with open(path, 'wb') as f:
        f.write(b'# yade-mss assembly: x y z r clumpId, one line per sphere, world units; each grain one clump '
                b'(clumpId = its label, or its place in the batch); #mss lines: exact mass properties at unit '
                b'density (yade_mss.readClumps, mssAssembly); ymport.textClumps reads the spheres.\n')
        for c0 in range(0, len(cids), CHUNK_CLUMPS):
            c1 = min(len(cids), c0 + CHUNK_CLUMPS)
            lo, hi = int(offsets[c0]), int(offsets[c1])
            f.write(_mss.formatClumpAssembly(np.ascontiguousarray(spheres[lo:hi], dtype=np.float64).tobytes(),
                                             (offsets[c0:c1 + 1] - lo).astype(np.int64).tobytes(),
                                             cids[c0:c1].tobytes(), heads[c0:c1].tobytes()))


CHUNK_CLUMPS = 1 << 12  # clumps formatted at once: a few MB of text (numbers and text are copied on the way)
FORMAT_ROWS = 1 << 15  # rows of a table formatted at once, likewise: 10^5 grains' tables are tens of MB of text


def _writeContacts(path, c):
    """contacts.csv: the scan's contacts (:class:`yade_mss.grains.ScanContacts`), a row each, as the csv module
    writes them (numbers as repr writes them, rows ended by CR LF)."""
    with open(path, 'wb') as f:
        f.write(b'a,b,faces,gap,x,y,z,nx,ny,nz\r\n')
        for x in range(0, len(c), FORMAT_ROWS):  # a chunk at a time: 10^6 contacts' text is tens of MB
            part = slice(x, x + FORMAT_ROWS)
            ints = np.column_stack([c.a[part], c.b[part], c.faces[part]]).astype(np.int64)
            numbers = np.column_stack([c.gaps[part], c.points[part], c.normals[part]]).astype(np.float64)
            f.write(_mss.formatRows(ints.tobytes(), 3, numbers.tobytes(), 7, 'shortest', ',', '\r\n'))


def writeVtk(path, b, ids):
    """The assembly for ParaView: legacy VTK polydata, one vertex per sphere with its radius (a Glyph filter's
    scale), its clump id, its grain's D and its smallest radius in voxels (what sets the time step)."""
    spheres, offsets = b.packed()
    counts = np.diff(offsets)
    n = len(spheres)
    keys = list(b.clumps)
    per = {'radius': spheres[:, 3],
           'clump_id': np.repeat(np.array([int(ids[k]) for k in keys], dtype=np.int64), counts),
           'dice': np.repeat(np.array([_number(b.rows[k]['dice']) or 0.0 for k in keys]), counts),
           'grain_r_min_voxels': np.repeat(np.array([_number(b.rows[k].get('r_min_voxels')) or 0.0 for k in keys]),
                                           counts)}
    with open(path, 'wb') as f:
        f.write(b'# vtk DataFile Version 3.0\nyade-mss assembly: spheres (radius, clump_id, dice)\nASCII\n'
                b'DATASET POLYDATA\nPOINTS %d double\n' % n)
        _rows(f, spheres[:, :3])
        f.write(b'VERTICES %d %d\n' % (n, 2 * n))
        _rows(f, np.column_stack([np.ones(n, dtype=np.int64), np.arange(n, dtype=np.int64)]))
        # a FIELD: every array is read (a reader takes only the first of several SCALARS by default)
        f.write(b'POINT_DATA %d\nFIELD spheres %d\n' % (n, len(per)))
        for name, values in per.items():
            kind = 'int' if name == 'clump_id' else 'double'
            f.write(b'%s 1 %d %s\n' % (name.encode(), n, kind.encode()))
            _rows(f, values[:, None])


def _rows(f, a, chunk=FORMAT_ROWS):
    """Writes the rows of the 2-D array *a*, separated by spaces, as np.savetxt's '%d' (an integer array) or
    '%.17g' writes them, formatted by the core a chunk of rows at a time."""
    whole = np.issubdtype(a.dtype, np.integer)
    for x in range(0, len(a), chunk):
        part = np.ascontiguousarray(a[x:x + chunk], dtype=np.int64 if whole else np.float64).tobytes()
        f.write(_mss.formatRows(part, a.shape[1], b'', 0, 'g17', ' ', '\n') if whole else
                _mss.formatRows(b'', 0, part, a.shape[1], 'g17', ' ', '\n'))


def _atomic(path, write):
    atomicWrite(path, write, 'batch')


def _write(path, data):
    with open(path, 'wb' if isinstance(data, bytes) else 'w') as f:
        f.write(data)


def drawPictures(outdir, b):
    """The report's pictures: the histograms (where a grain is ok; D's flag line at ``b.flagAt``) and a segmented
    scan's section. They need only the rows: a batch draws them in a child while it counts the contacts and
    writes the other outputs (:func:`yade_mss.base.alongside`; importing matplotlib alone takes a few tenths of a
    second)."""
    if b.results:
        _charts(outdir, b)
    if getattr(b, 'segmented', None) is not None:
        _segmentationPicture(outdir, b.segmented)


CHARTS_TAG = ('<img src="report_distributions.png" alt="histograms of D, of the sphere counts and of the '
              'smallest radii">')
SEGMENTATION_TAG = ('<br><img src="report_segmentation.png" alt="a section of the binary scan and of its '
                    'grains">')


def _charts(outdir, b):
    """Three histograms that show something: D (the flag line drawn), spheres per grain (integer bins; one
    value is said, not drawn as one bar) and the smallest radius in voxels (what sets the time step)."""
    ok = [b.rows[k] for k in b.results]
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(13, 3.8), dpi=100)
    d = [float(r['dice']) for r in ok]
    a1.hist(d, bins=min(30, max(5, len(d) // 2)), color='#4c72b0')
    a1.axvline(b.flagAt, color='#c44e52', lw=1, label='flagged above')
    a1.legend(fontsize=8)
    a1.set_xlabel('Dice mismatch D (eq. 27, on the grain\'s own grid)')
    a1.set_ylabel('grains')
    n = [int(r['spheres']) for r in ok]
    if min(n) == max(n):
        a2.text(0.5, 0.5, 'every grain: %d spheres' % n[0], ha='center', va='center', transform=a2.transAxes)
        a2.set_xticks([])
        a2.set_yticks([])
    else:
        step = max(1, (max(n) - min(n) + 1) // 30)
        a2.hist(n, bins=np.arange(min(n), max(n) + step + 1, step) - 0.5, color='#55a868')
        a2.set_ylabel('grains')
    a2.set_xlabel('spheres per grain')
    rv = [_number(r.get('r_min_voxels')) for r in ok]
    rv = [x for x in rv if x is not None]
    if rv:
        a3.hist(rv, bins=min(30, max(5, len(rv) // 2)), color='#8172b2')
        a3.set_ylabel('grains')
    a3.set_xlabel('smallest radius per grain (voxels)')
    fig.suptitle('%s generated' % grains(len(ok)))
    fig.tight_layout()
    _atomic(os.path.join(outdir, 'report_distributions.png'), fig.savefig)
    plt.close(fig)


def _segmentationPicture(outdir, seg):
    """The section of a segmented binary scan: the scan and its grains side by side (report_segmentation.png)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    from matplotlib.colors import ListedColormap
    labels = seg['labels']
    rng = np.random.default_rng(0)
    colours = np.vstack([[1, 1, 1], rng.uniform(0.15, 0.95, (max(1, int(labels.max())), 3))])
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(15, 5), dpi=100)
    # the solid grey on white, as a scan is seen (black solid read as a negative)
    a1.imshow(seg['binary'].T, origin='lower', cmap=ListedColormap([[1, 1, 1], [0.45, 0.45, 0.45]]), vmin=0,
              vmax=1, interpolation='nearest')
    a1.set_title('the binary scan, section z = %d (solid grey)' % seg['z'])
    a2.imshow(labels.T, origin='lower', cmap=ListedColormap(colours), vmin=0, vmax=len(colours) - 1,
              interpolation='nearest')
    a2.set_title('its grains (%s in the volume; a colour each)' % grains(seg['grains']))
    for a in (a1, a2):
        a.set_xlabel('x (voxels)')
        a.set_ylabel('y (voxels)')
    sizes = np.asarray(seg.get('sizes') or [], dtype=float)
    if sizes.size:
        d = np.cbrt(6.0 * sizes / np.pi)  # each grain's equivalent diameter, voxels
        a3.hist(d, bins=min(40, max(5, sizes.size // 3)), color='0.5', edgecolor='k')
        a3.set_xlabel('equivalent diameter (voxels: the ball of the grain\'s volume)')
        a3.set_ylabel('grains')
        a3.set_title('the grains\' sizes (median %.3g voxels)' % float(np.median(d)))
    fig.tight_layout()
    _atomic(os.path.join(outdir, 'report_segmentation.png'), fig.savefig)
    plt.close(fig)


_SHOWN = ['label', 'file', 'status', 'problems', 'voxels', 'spheres', 'dice', 'eta', 'protrusion', 'r_min_voxels',
          'thickness_voxels', 'time_step', 'contacts_ct', 'contacts_kept', 'contacts_assembly', 'seconds', 'message']


def _report(outdir, b, density, young):
    rows = list(b.rows.values())
    counts = {s: sum(1 for r in rows if r['status'] == s) for s in ('ok', 'skipped', 'failed')}
    notes = []
    h = getattr(b, 'voxelSize', None)
    if h is not None:
        notes.append('Voxel edge %g m (--voxel-size, --scale).' % h if getattr(b, 'voxelSizeGiven', False) else
                     'Voxel edge 1: no --voxel-size was given, so lengths, masses and the time step are in voxels, '
                     'not metres. Give --voxel-size, the voxel edge in metres, for YADE.')
    cut = sum(1 for r in rows if int(r.get('touches_border') or 0))
    if cut:
        notes.append('%d of %s are cut by the volume\'s border: their clumps end where the scan does '
                     '(--exclude-border skips them).' % (cut, grains(len(rows))))
    if counts['failed']:
        notes.append('%s failed: see %s below.' % (grains(counts['failed']), 'its message' if counts['failed'] == 1
                                                    else 'their messages'))
    small = sum(1 for k in b.rows if b.kinds.get(k) == 'too small')
    if small:
        notes.append('%s too small for the radius bound (rMin, rMinVoxels): not in the assembly.'
                     % grains(small))
    if b.timeStep is not None:
        notes.append('The assembly\'s critical time step is %.3g s (PWaveTimeStep: the smallest radius times '
                     'sqrt(density / young), density %g, young %g), set by %s.'
                     % (b.timeStep, density, young, ', '.join(_html(k) for k in b.setBy[:10])))
    if getattr(b, 'contacts', None):
        c = b.contacts
        if c['pairs'] == 0:
            notes.append(gapsText(c))
        else:
            notes.append('Contacts, counted with one tolerance (grains within %g voxel%s: --contact-gap): %d pairs '
                         'of grains in the scan, %d of them between generated grains, %d of those kept in the '
                         'assembly (clumps within %.1f voxel; largest overlap %.2f voxels); %d pairs of clumps in '
                         'the assembly. Coordination number %.2f in the scan, %.2f in the assembly.'
                         % (c['gap'], _s(c['gap']), c['pairs'], c['between'], c['kept'], KEPT_GAP, c['overlap'],
                            c['assembly'], c['coordinationScan'], c['coordinationAssembly'])
                         + (' Lost: %s.' % reasonsText(c['lost']) if c.get('lost') else ''))
    seg = getattr(b, 'segmented', None)
    if seg is not None:
        i = seg.get('info', {})
        notes.append('The scan was binary: it was segmented here into %s: %s. Dropped: %d specks (%d voxels, pieces '
                     'under %d voxels) and %d segments under --min-voxels (%d voxels); %d voxels of pores filled for '
                     'the distance transform only (the grains keep the scan\'s pores). The labels are in '
                     '<a href="labels.npy">labels.npy</a>: inspect or correct them, then run the batch on them (or '
                     'give markers of your own: --segment-markers). Below, the section z = %d and the grains\' '
                     'sizes.%s' % (grains(seg['grains']), _html(i.get('method', '')), i.get('specks', 0),
                                   i.get('speckVoxels', 0), SPECK_VOXELS, i.get('small', 0), i.get('smallVoxels', 0),
                                   i.get('poreVoxels', 0), seg['z'], SEGMENTATION_TAG))
    generated = sum(_number(r['seconds']) or 0.0 for r in rows)
    previewed = set(getattr(b, 'previewed', []))

    def thumb(k):
        if k not in previewed:
            return '<td></td>'
        url = html.escape('grains/' + urllib.parse.quote(k + '.png'), quote=True)
        return '<td><a href="%s"><img src="%s" width="360" alt="%s"></a></td>' % (url, url, _html(k))

    def cls(k):
        return {'failed': 'bad', 'flagged': 'warn', 'too small': 'warn'}.get(b.kinds.get(k), '')
    head = ('<!doctype html><html><head><meta charset="utf-8"><title>mss batch</title><style>'
            'td,th{padding:2px 8px;font:12px sans-serif;vertical-align:top}tr:nth-child(even){background:#eee}'
            'tr.bad td{background:#f4c7c3}tr.warn td{background:#fce8b2}p.note{background:#fce8b2;padding:4px}'
            # the table fits the page: long texts wrap in columns wide enough to read, the rest scrolls
            'div.grains{overflow-x:auto}td.problems{min-width:22em}td.message,td.file{max-width:28em;'
            'overflow-wrap:anywhere}img{max-width:100%%}'
            '</style></head><body><h1>mss batch</h1>'
            '<p>%s: %d ok, %d skipped, %d failed. This run, up to this report: %.2f s (the console\'s last line also '
            'counts the writing of the outputs), %s generated%s; generation time of all grains '
            '%.2f s. Files: '
            '<a href="assembly.txt">assembly.txt</a>, <a href="assembly.vtk">assembly.vtk</a> (ParaView), '
            '<a href="grains.csv">grains.csv</a>.</p>%s%s<h2>Grains, worst first</h2><div class="grains"><table><tr>'
            '<th>#</th>%s<th>preview</th></tr>'
            % (grains(len(rows)), counts['ok'], counts['skipped'], counts['failed'], b.seconds, grains(b.generated),
               ', %s reused from an earlier run with the same input and options' % grains(b.reused)
               if getattr(b, 'reused', 0) else '', generated,
               ''.join('<p class="note">%s</p>' % n for n in notes), CHARTS_TAG if b.results else '',
               ''.join('<th>%s</th>' % c for c in _SHOWN)))

    def page(p):  # a row at a time: the table of 10^5 grains is tens of MB
        with open(p, 'w') as f:
            f.write(head)
            f.writelines('<tr class="%s"><td>%d</td>%s%s</tr>' % (cls(k), i, ''.join(
                '<td class="%s">%s</td>' % (c, _html(b.rows[k].get(c, ''))) for c in _SHOWN), thumb(k))
                for i, k in enumerate(b.ranked, 1))
            f.write('</table></div></body></html>')
    _atomic(os.path.join(outdir, 'report.html'), page)


def _html(v):
    """Text for the report: escaped for content and attributes alike (quotes too); bytes of a file name that
    are not UTF-8 shown as their escapes."""
    if isinstance(v, float):
        v = '%.4g' % v
    return html.escape(str(v).encode('utf-8', 'backslashreplace').decode('utf-8'), quote=True)
