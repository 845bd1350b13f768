"""From a CT specimen or a folder of grains to a DEM assembly: :func:`batch` (``mss batch``).

Each grain is cropped to its bounding box plus the double zero hull (eq. 6), generated single-threaded, placed
at its true position, and written atomically to OUTDIR/grains/ (``KEY.npz`` result, ``KEY.csv`` spheres, then
``KEY.json``, the mark that it is done and with which options). A rerun with the same options skips what is
done, so an interrupted run loses nothing already written. Grains run side by side in processes
(``--workers``) or as tasks on a Dask cluster (``--scheduler``); only a grain's cropped sub-volume travels. The
results do not depend on which way or worker ran what (generation is deterministic, one thread per grain).
At the end: ``assembly.txt`` (every sphere, ``x y z r clumpId``, with each clump's exact mass properties on a
``#mss clump`` line for ``readClumps``), ``grains.csv`` and ``report.html``.
"""

import contextlib
import hashlib
import json
import os
import stat
import sys
import time
import zlib
from collections.abc import Mapping

import numpy as np

from ..base import (alongside, atomicWrite, flag, folderLock, integer, number, refuseLinkedFolders,
                    refuseOverInputs, releaseFreed, requireRegularFile, slowPhase, split, vector3)
from ..exports import MAX_TEMPLATES, writeTemplates
from ..grains import (GENERATE_OPTIONS, MESH_EXT, VOLUME_EXT, ContactIndex, MassProperties, MssResult,
                      ScanContacts, binaryValue, generateWith,
                      SPECK_VOXELS, optionTable, pieces, readVolume, regions, scanContacts, segmentScan, slabVoxels,
                      valueRange)
from . import _manifest, _report
from ._pools import WORKER_DIED, checkScheduler, executor, freeCores
from ._report import COLUMNS

TOO_SMALL = 'exceeds the largest inscribed radius'  # the core's message when rMin leaves a grain no sphere
RELEASE_EVERY = 1000  # grains between two hand-backs of freed memory (releaseFreed: a few ms)
DIGEST = '_input'  # a row's key, from the worker to the batch: the grain's input digest (not a column)


class GrainTask(object):
    """One grain to generate: a cropped sub-volume (with its world origin) or a file; small enough to send.
    *digest*: of what it is made from (the crop's voxels, box and origin, its contact points and neighbours, or
    the file's bytes), so that a rerun reuses a result only for the same input; computed when first asked for
    (where the grain runs, from the crop it cuts anyway).

    A labelled volume's grain holds its *region*, the *volume* and the scan's contact *index* instead of its
    arrays: its crop, neighbours and contact points are cut when asked for, so that a batch holds the voxels
    and points of the grains in flight only (10^5 grains of a scan)."""

    __slots__ = ('key', 'options', 'label', 'path', 'voxelSize', 'origin', 'voxels', 'touchesBorder', '_crop',
                 '_neighbours', '_contacts', '_region', '_volume', '_index', '_digest')

    def __init__(self, key, options, label=None, path=None, crop=None, voxelSize=None, origin=None, voxels=0,
                 touchesBorder=False, contacts=None, neighbours=None, region=None, volume=None, index=None):
        self.key, self.options, self.label, self.path = key, options, label, path
        self._contacts = contacts  # the points its spheres must reach (its neighbours in the volume), or None
        self._crop, self._neighbours = crop, neighbours
        self._region, self._volume, self._index = region, volume, index
        self.voxelSize, self.origin = voxelSize, origin
        self.voxels, self.touchesBorder = voxels, touchesBorder
        self._digest = None

    @property
    def crop(self):
        if self._crop is None and self._region is not None:
            return self._region.crop(self._volume)[0]
        return self._crop

    @property
    def neighbours(self):
        if self._neighbours is None and self._region is not None and self._index is not None:
            return self._region.neighbours(self._volume)
        return self._neighbours

    @property
    def contacts(self):
        """The points to reach, 6 numbers each (point, normal into the grain), or None (contacts off, a file)."""
        if self._contacts is None and self._index is not None:
            return self._index(self.label)
        return self._contacts

    @property
    def digest(self):
        if self._digest is None:
            crop = self.crop
            self._digest = (_cropDigest(crop, self.voxelSize, self.origin, self.contacts, self.neighbours)
                            if crop is not None else _fileDigest(self.path))
        return self._digest

    def cut(self):
        """(crop, contact points, neighbours), each cut once (a scan's crop and neighbours from one read of its
        box), and the digest from them."""
        contacts = self.contacts
        if self._crop is None and self._region is not None:
            crop, near = self._region.cut(self._volume, 2, self._index is not None)
        else:
            crop = self.crop
            near = self.neighbours if crop is not None else None
        if self._digest is None:
            self._digest = (_cropDigest(crop, self.voxelSize, self.origin, contacts, near) if crop is not None
                            else _fileDigest(self.path))
        return crop, contacts, near

    # A task travels (to a worker process, a Dask worker) with its voxels deflated, a boolean crop packed to a
    # bit a voxel first: Dask warned of every task over a megabyte ("Large object ... detected in task graph");
    # a grain's crop packs to about a hundredth. Other arrays (a grain's own volume file) keep their values.
    def __getstate__(self):
        state = {n: getattr(self, n) for n in self.__slots__}
        state.update(_region=None, _volume=None, _index=None, _contacts=self.contacts)
        for name in ('_crop', '_neighbours'):
            a = getattr(self, name[1:])
            if a is None:
                state[name] = None
                continue
            a = np.ascontiguousarray(a)
            raw = np.packbits(a, axis=None).tobytes() if a.dtype == bool else a.tobytes()
            state[name] = (a.shape, a.dtype.str, zlib.compress(raw, 1))
        return state

    def __setstate__(self, state):
        for name in ('_crop', '_neighbours'):
            if state.get(name) is not None:
                shape, dtype, packed = state[name]
                raw = np.frombuffer(zlib.decompress(packed), dtype=np.uint8)
                if np.dtype(dtype) == bool:
                    state[name] = np.unpackbits(raw, count=int(np.prod(shape))).astype(bool).reshape(shape)
                else:
                    state[name] = raw.view(np.dtype(dtype)).reshape(shape).copy()
        for n in self.__slots__:
            setattr(self, n, state.get(n))


def _cropDigest(crop, voxelSize, origin, contacts=None, neighbours=None):
    a = np.ascontiguousarray(crop)
    h = hashlib.sha256()
    points = np.ascontiguousarray(contacts if contacts is not None else np.zeros((0, 6)), dtype=np.float64)
    h.update(json.dumps({'shape': list(a.shape), 'dtype': a.dtype.str, 'voxelSize': voxelSize,
                         'origin': [float(x) for x in origin], 'contacts': len(points)}).encode())
    h.update(points.tobytes())  # the points' bytes: their text cost a grain 50 us
    h.update(a.tobytes())
    if neighbours is not None:
        h.update(np.ascontiguousarray(neighbours).tobytes())
    return h.hexdigest()


def _fileDigest(path):
    requireRegularFile('batch', path)
    h = hashlib.sha256()
    with open(path, 'rb') as f:
        for block in iter(lambda: f.read(1 << 20), b''):
            h.update(block)
    return h.hexdigest()


def _safe(text):
    """A name for files and keys: letters, digits, '.', '-' and '_' only (any other character, or byte of a
    name that is not UTF-8, becomes '_')."""
    return ''.join(c if (c.isascii() and (c.isalnum() or c in '.-_')) else '_' for c in text) or '_'


def fileKeys(files):
    """One key per file, never shared: 'file_' and the file's name (extension included); names that would be
    the same (the same name in two folders, or after making them safe) get a digest of their full path too."""
    keys = ['file_' + _safe(os.path.basename(f)) for f in files]
    seen = {}
    for k in keys:
        seen[k.lower()] = seen.get(k.lower(), 0) + 1
    out = []
    for f, k in zip(files, keys):
        if seen[k.lower()] > 1:
            k += '_' + hashlib.sha256(os.fsencode(os.path.abspath(f))).hexdigest()[:10]
        out.append(k)
    return out


def runGrain(task):
    """Generates one grain (one thread); never raises: a failure is a row with its message."""
    row = _row(task)
    t0 = time.perf_counter()
    try:
        opts = dict(task.options, threads=1)
        crop, contacts, near = task.cut()
        row[DIGEST] = task.digest  # the input's, for the record: taken off the row before it is stored
        t0 = time.perf_counter()  # the grain's time is its generation's: cutting and digesting are the batch's
        if crop is not None:
            points = np.asarray(contacts, dtype=float).tolist() if contacts is not None else []
            r = generateWith(crop, dict(opts, voxelSize=task.voxelSize, origin=task.origin), points, near)
        else:
            r = generateWith(task.path, opts)
        r.grain = None  # the crop: held per grain it would grow with the volume; previews crop again
        h = r.grid['voxelSize']
        row.update(status='ok', spheres=len(r), dice=r.metrics['dice'], eta=r.metrics['eta'],
                   protrusion=r.metrics.get('protrusion', ''), r_min=r.metrics['smallestRadius'],
                   r_min_voxels=r.metrics['smallestRadius'] / h, thickness_voxels=r.metrics['inscribedRadius'] / h,
                   contacts_ct=0 if contacts is None else len(contacts),
                   contact_spheres=r.metrics.get('contactsAdded', 0),
                   seconds=time.perf_counter() - t0)
        return task.key, row, r
    except ValueError as e:
        if TOO_SMALL not in str(e):
            return _failed(task, row, t0, e)
        # reported as such, never shrunk under the bound: the assembly lacks it, the report says why
        row.update(status='skipped', seconds=time.perf_counter() - t0, message='too small for the radius bound '
                   '(rMin, rMinVoxels): %s' % e)
        return task.key, row, None
    except Exception as e:  # noqa: BLE001 (any grain's failure is recorded, the batch goes on)
        return _failed(task, row, t0, e)


def _failed(task, row, t0, e):
    row.update(status='failed', seconds=time.perf_counter() - t0, message='%s: %s' % (type(e).__name__, e))
    return task.key, row, None


def _row(task):
    """A grain's row before it is generated: what the task says of it, no figures yet."""
    return dict(_blank(), label=task.label if task.label is not None else '', file=task.path or '',
                voxels=task.voxels, touches_border=int(bool(task.touchesBorder)))


def _blank():
    return dict({c: '' for c in COLUMNS}, spheres=0, voxels=0, touches_border=0)


def _failedRow(task, message):
    """The row of a grain whose worker died: as :func:`runGrain` records a failure."""
    return task.key, dict(_row(task), status='failed', message=message), None


def _executor(workers, scheduler, security=None, connectTimeout=5.0, tasks=None):
    """Where the grains run (:func:`yade_mss.specimens._pools.executor`), with this module's grain work."""
    return executor(workers, scheduler, runGrain, runGrains, _failedRow, security, connectTimeout, tasks)


def runGrains(tasks):
    """Several grains in one task (Dask)."""
    return [runGrain(t) for t in tasks]


def _optionsKey(gen, extra):
    text = json.dumps({'generate': gen, 'input': extra}, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _atomic(path, write):
    atomicWrite(path, write, 'batch')


def _inputs(inputs):
    """Files from the arguments: files as given, directories by their supported files (sorted)."""
    files = []
    for item in inputs:
        item = os.fspath(item)
        if os.path.isdir(item):
            files += sorted(os.path.join(item, f) for f in os.listdir(item)
                            if os.path.splitext(f)[1].lower() in MESH_EXT + VOLUME_EXT)
        elif os.path.exists(item):
            files.append(item)
        else:
            raise ValueError('batch: %s: no such file or directory' % item)
    if not files:
        raise ValueError('batch: no mesh or volume file in %s' % ', '.join(map(str, inputs)))
    return files


def checkLabelled(vol, name, segment=False, memoryLimit=None):
    """Refuses a binary scan (two values, in several pieces) given as a labelled volume: it would be one grain
    of all its pieces. *segment*: the scan is meant to be binary; refused if it is not."""
    value = binaryValue(vol, memoryLimit)
    if segment:
        if value is None and not any(valueRange(vol, slabVoxels(memoryLimit))):
            raise ValueError('batch: %s holds no solid voxel: every voxel is 0 (the background)' % name)
        if value is None:
            raise ValueError('batch: %s: segment applies to a binary scan (0 and one other value); this volume holds '
                             'labels: give it without --segment' % name)
        return
    if value is not None:
        n = pieces(vol, memoryLimit)
        if n > 1:
            raise ValueError('batch: %s holds two values (0 and %d) in %d separate pieces: a binary scan, not '
                             'labelled grains (as labels it would be one grain of all %d). Give --segment '
                             '(segment=True) to cut it into grains here (distance transform, h-maxima markers, '
                             'marker watershed; the labels are written to OUT/labels.npy), or label it first '
                             '(scipy.ndimage.label for grains apart, skimage.segmentation.watershed for touching '
                             'ones)' % (name, value, n, n))


def makeTasks(inputs, options, voxelSize=None, origin=None, minVoxels=0, excludeBorder=False, labels=None,
              scan=None):
    """The grains of the inputs: a labelled volume (one file, or an array) gives one task per label, read once;
    several files give one task each. Grains under *minVoxels* or (with *excludeBorder*) cut by
    the border come back as skipped rows instead. *scan*: a dict that gets the labelled volume's ``box`` (the
    world box its voxels fill, [lower, upper], as the grains are placed), for porosity().

    :return: (tasks, skipped rows {key: row}, options key, the volume's contacts or None)
    """
    array = inputs if isinstance(inputs, np.ndarray) else None
    files = ['(array)'] if array is not None else _inputs(inputs)
    h = 1.0 if voxelSize is None else float(voxelSize)
    if not (h > 0 and np.isfinite(h)):
        raise ValueError('batch: voxel size must be > 0, got %r' % (voxelSize,))
    org = np.zeros(3) if origin is None else np.asarray(origin, dtype=float).reshape(3)
    key = _optionsKey(options, {'voxelSize': h, 'origin': org.tolist(), 'minVoxels': minVoxels,
                                'excludeBorder': bool(excludeBorder)})
    # scale multiplies a volume's coordinates as read (its voxel edge and origin: here, once for all its
    # grains) and a mesh's vertices (in generate); a mesh's voxelSize is its generation grid, in world units
    meshGrid = h
    scale = float(options.get('scale') or 1.0)
    h, org = h * scale, org * scale
    voxelOptions = {o: v for o, v in options.items() if o != 'scale'}
    tasks, skipped = [], {}
    volumes = [f for f in files if os.path.splitext(f)[1].lower() in VOLUME_EXT]
    if array is not None or (len(files) == 1 and volumes):
        vol = readVolume(files[0]) if array is None else array
        checkLabelled(vol, files[0], memoryLimit=options.get('memoryLimit'))
        if scan is not None:
            scan['box'] = [(org - h / 2).tolist(), (org + h * (np.array(vol.shape) - 0.5)).tolist()]
        limit = options.get('memoryLimit')  # the volume is read by slabs under it: a CT larger than it is fine
        gap = options.get('contactGap', 1.0)
        found = scanContacts(vol, h, org, limit, gap) if options.get('contacts', True) else None
        found_regions = regions(vol, labels, limit)
        if not found_regions:
            raise ValueError('batch: %s holds no grain: %s' % (
                files[0], 'none of the labels %s is in it' % labels if labels else
                'every voxel is 0 (the background)'))
        why = {}  # the grains not generated, and why
        for reg in found_regions:
            if reg.voxels < minVoxels:
                why[reg.label] = '%d voxels, under --min-voxels %d' % (reg.voxels, minVoxels)
            elif excludeBorder and reg.touchesBorder:
                why[reg.label] = 'cut by the volume\'s border (--exclude-border)'
        # no contact balls toward grains the batch skips (specks under --min-voxels, grains the border cuts with
        # --exclude-border): they are not in the assembly. A grain left out by labels= is another run's: its
        # neighbours keep their balls toward it, as each would alone (generate(volume, label=...))
        index = None
        if found is not None:
            out = np.fromiter(why, dtype=np.int64, count=len(why))
            index = ContactIndex(found, ~(np.isin(found.a, out) | np.isin(found.b, out)))
        for reg in found_regions:
            k = 'label_%d' % reg.label
            if reg.label in why:
                skipped[k] = dict(_blank(), label=reg.label, voxels=reg.voxels,
                                  touches_border=int(reg.touchesBorder), status='skipped', message=why[reg.label])
            else:
                start = np.array([s.start for s in reg.box]) - 2  # the crop's voxel (0, 0, 0), as reg.crop says
                tasks.append(GrainTask(k, voxelOptions, label=reg.label, path=files[0] if array is None else None,
                                       voxelSize=h, origin=tuple((org + h * start).tolist()), voxels=reg.voxels,
                                       touchesBorder=reg.touchesBorder, region=reg, volume=vol, index=index))
        return tasks, skipped, key, found
    if labels:
        raise ValueError('batch: --labels applies to one labelled volume')
    for f, k in zip(files, fileKeys(files)):
        try:
            if os.path.splitext(f)[1].lower() in VOLUME_EXT:  # a grain's volume: all its voxels are the grain
                vol = readVolume(f)
                opts = {o: v for o, v in voxelOptions.items() if o != 'resolution'}
                tasks.append(GrainTask(k, opts, path=f, crop=np.asarray(vol), voxelSize=h,
                                       origin=org.tolist(), voxels=int(np.count_nonzero(vol))))
            elif voxelSize is not None and 'resolution' not in options:  # a mesh's grid at that voxel edge
                tasks.append(GrainTask(k, dict(options, voxelSize=meshGrid), path=f))
            else:
                tasks.append(GrainTask(k, options, path=f))
        except (OSError, ValueError) as e:  # a bad file is recorded, the batch goes on
            skipped[k] = dict(_blank(), file=f, status='failed', message='%s: %s' % (type(e).__name__, e))
    return tasks, skipped, key, None


class Batch(object):
    """What a batch did: rows (one per grain, in key order) and the results of the grains that are ok.

    :ivar rows: {key: row}, the columns of grains.csv
    :ivar results: {key: :class:`MssResult`} of the grains that are ok; with an output folder each is read from
        its grains/KEY.npz when asked for (a batch of 10^5 grains holds their spheres packed, not their results)
    :ivar scanContacts: the scan's contacts (:class:`yade_mss.grains.ScanContacts`), or None
    :ivar seconds: this run's wall time
    :ivar generated: grains generated in this run (ok: a grain that failed is not generated)
    :ivar reused: grains whose results an earlier run of the same input and options had written
    :ivar upToDate: True where the output folder already held this very batch, finished: nothing was done
    :ivar timeStep: the assembly's critical time step (the least a grain allows), or None without a grain
    :ivar setBy: the keys of the grains that set it (within 10% of the least)
    """

    def __init__(self):
        self.rows, self.results, self.seconds, self.generated, self.reused = {}, {}, 0.0, 0, 0
        self.timeStep, self.setBy, self.upToDate, self._scan, self._scanFile = None, [], False, None, None
        self.clumps = self.results  # what the batch's own passes read: centers, radii and targetMass a grain
        self._stored, self._packed = False, None

    def keep(self, key, result):
        """Holds a generated grain: its result whole, or with an output folder (:meth:`storing`) its spheres and
        mass properties packed (:class:`PackedClumps`), the result read back from its file when asked for."""
        if self._stored:
            self.clumps.add(key, result)
        else:
            self.results[key] = result

    def storing(self):
        """The grains' results are in the output folder: hold only what the batch's passes need of them (a
        result whole, its metrics and grid, is several kB: 10^5 grains of a scan)."""
        self._stored, self.clumps = True, PackedClumps()

    def packed(self):
        """(spheres, offsets) of the clumps, in their order (:func:`yade_mss.specimens._report.packed`)."""
        if self._packed is None:
            self._packed = self.clumps.packed() if self._stored else _report.packed(self.clumps)
        return self._packed

    def finish(self, outdir, order):
        """The results and clumps in key order (*order*: the sort key of a grain's key); with an output folder
        the results are read from it when asked for."""
        if self._stored:
            self.clumps = self.clumps.ordered(order)
            self.results = _StoredResults(outdir, self.clumps)
        else:
            self.results = self.clumps = dict(sorted(self.results.items(), key=lambda kv: order(kv[0])))

    @property
    def failed(self):
        return [k for k, r in self.rows.items() if r['status'] == 'failed']

    @property
    def scanContacts(self):
        """The scan's contacts (:class:`yade_mss.grains.ScanContacts`: columns; indexing or iterating gives
        :func:`findContacts`' dicts), or None (a folder of grains, contacts off); read from the output folder's
        contacts.csv when the batch was up to date."""
        if self._scan is None and self._scanFile is not None:
            import csv
            with open(self._scanFile, newline='') as f:
                self._scan = ScanContacts.fromDicts(
                    (dict(a=int(r['a']), b=int(r['b']), faces=int(r['faces']), gap=float(r['gap']),
                          point=(float(r['x']), float(r['y']), float(r['z'])),
                          normal=(float(r['nx']), float(r['ny']), float(r['nz']))) for r in csv.DictReader(f)),
                    (getattr(self, 'contacts', None) or {}).get('gap', 1.0))
        return self._scan

    @scanContacts.setter
    def scanContacts(self, value):
        self._scan = value


class PackedClumps(Mapping):
    """The generated grains' spheres and exact mass properties (unit density), packed: every sphere a row
    x y z r of one growing array, every grain's mass properties a row of another; {key: a view with the
    ``centers``, ``radii`` and ``targetMass`` of an :class:`MssResult`}, made when asked for. What the batch's
    passes (contacts, the assembly's files) read of its results: a result, or arrays of each grain's own, cost
    10^5 grains kilobytes each."""

    MASS = 13  # volume, centroid (3), inertia (9)

    def __init__(self):
        self._at = {}  # key -> its place
        self._spheres, self._mass = np.empty((1024, 4)), np.empty((256, self.MASS))
        self._starts, self._counts = np.empty(256, dtype=np.int64), np.empty(256, dtype=np.int64)
        self._rows = 0

    def add(self, key, result):
        n, x = len(result.radii), len(self._at)
        # grown in place by a quarter (realloc: a large block is remapped, not copied), no view of them held
        # until the grains are all in
        if self._rows + n > len(self._spheres):
            self._spheres.resize((max(self._rows + n, len(self._spheres) * 5 // 4), 4), refcheck=False)
        if x == len(self._mass):
            for a in (self._mass, self._starts, self._counts):
                a.resize((len(a) * 5 // 4,) + a.shape[1:], refcheck=False)
        self._spheres[self._rows:self._rows + n, :3] = result.centers
        self._spheres[self._rows:self._rows + n, 3] = result.radii
        m = result.targetMass
        self._mass[x, 0], self._mass[x, 1:4], self._mass[x, 4:] = m.volume, m.centroid, m.inertia.ravel()
        self._starts[x], self._counts[x] = self._rows, n
        self._rows += n
        self._at[key] = x

    def __getitem__(self, key):
        x = self._at[key]
        return _Clump(self._spheres[self._starts[x]:self._starts[x] + self._counts[x]], self._mass[x])

    def __contains__(self, key):
        return key in self._at

    def __iter__(self):
        return iter(self._at)

    def __len__(self):
        return len(self._at)

    def ordered(self, order):
        """The same grains in key order (*order*: the sort key of a key), packed in that order: where they came
        out of order (workers), the arrays are copied once."""
        keys = sorted(self._at, key=order)
        places = np.array([self._at[k] for k in keys], dtype=np.int64)
        if np.all(places == np.arange(len(places))):
            self._at = {k: x for x, k in enumerate(keys)}
            return self
        out = PackedClumps()
        out._mass, counts = self._mass[places], self._counts[places]
        out._starts = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        out._spheres = np.empty((int(counts.sum()), 4))
        for x, (s, c) in enumerate(zip(self._starts[places].tolist(), counts.tolist())):  # no index array
            out._spheres[out._starts[x]:out._starts[x] + c] = self._spheres[s:s + c]
        self._spheres = None  # let go before the next pass
        out._counts = counts
        out._rows, out._at = len(out._spheres), {k: x for x, k in enumerate(keys)}
        return out

    def masses(self):
        """The mass properties of the clumps, a row each in their order (:data:`MASS` numbers: volume, centroid,
        inertia row by row)."""
        return self._mass[np.fromiter(self._at.values(), dtype=np.int64, count=len(self._at))]

    def packed(self):
        """(spheres, offsets): :func:`yade_mss.specimens._report.packed`'s, without a copy (in key order after
        :meth:`ordered`)."""
        n = len(self._at)
        return self._spheres[:self._rows], np.concatenate([self._starts[:n], [self._rows]]).astype(np.int64)


class _Clump(object):
    """One grain of :class:`PackedClumps`: views of its rows."""

    __slots__ = ('_spheres', '_mass')

    def __init__(self, spheres, mass):
        self._spheres, self._mass = spheres, mass

    @property
    def centers(self):
        return self._spheres[:, :3]

    @property
    def radii(self):
        return self._spheres[:, 3]

    @property
    def targetMass(self):
        return MassProperties(self._mass[0], self._mass[1:4], self._mass[4:])

    def __len__(self):
        return len(self._spheres)


class _StoredResults(Mapping):
    """The results of a finished batch's grains, each read from OUTDIR/grains/KEY.npz when asked for (kept
    once read: a caller asks for a few, or walks through them)."""

    CACHED = 256  # results held once read: a walk through 10^5 grains holds these, not every one

    def __init__(self, outdir, keys):
        self._outdir, self._keys, self._loaded = outdir, dict.fromkeys(keys), {}

    def __contains__(self, key):
        return key in self._keys

    def __getitem__(self, key):
        if key not in self._loaded:
            if key not in self._keys:
                raise KeyError(key)
            if len(self._loaded) >= self.CACHED:
                del self._loaded[next(iter(self._loaded))]
            self._loaded[key] = MssResult.load(os.path.join(self._outdir, 'grains', key + '.npz'))
        return self._loaded[key]

    def __iter__(self):
        return iter(self._keys)

    def __len__(self):
        return len(self._keys)


_STATE = ('timeStep', 'setBy', 'contacts', 'ranked', 'kinds', 'flagAt', 'previewed', 'voxelSize', 'voxelSizeGiven',
          'scanBox')


def _state(b):
    """What a finished batch gives back, for its manifest."""
    out = {name: getattr(b, name, None) for name in _STATE}
    out['rows'] = b.rows
    out['scan'] = b.scanContacts is not None
    return out


def _upToDate(outdir, state, seconds):
    """The Batch of a finished run in *outdir*, from its manifest's *state*: nothing generated, nothing read but
    the manifest (results and contacts when asked for)."""
    b = Batch()
    b.rows = dict(state['rows'])
    b.results = _StoredResults(outdir, [k for k, r in b.rows.items() if r['status'] == 'ok'])
    for name in _STATE:
        setattr(b, name, state.get(name))
    if state.get('scan'):
        b._scanFile = os.path.join(outdir, 'contacts.csv')
    b.reused, b.upToDate, b.seconds = len(b.results), True, seconds
    return b


def _runKey(inputs, options, extra):
    """The manifest's key of a batch: its inputs' identity on disk and every option."""
    if isinstance(inputs, np.ndarray):
        ident = _manifest.inputIdentity(array=inputs)
    else:
        ident = _manifest.inputIdentity(files=_inputs(inputs))
    return json.loads(json.dumps({'inputs': ident, 'generate': options, 'batch': extra}, sort_keys=True,
                                 default=str))


META_BYTES = 1 << 24  # a grain's record is its row and digests: a few KB


def grainRecord(outdir, key):
    """(record, result) of the grain KEY that a batch wrote to *outdir*, checked: the record (grains/KEY.json,
    bounded) must hold the digest of its own row, and every file the grain wrote (.npz, .csv, .png) the digest
    recorded when it was written; None for a record missing, unreadable, edited, or whose files were swapped,
    truncated or edited since (the result None for a grain that was skipped)."""
    g = os.path.join(outdir, 'grains')
    path = os.path.join(g, key + '.json')
    try:
        requireRegularFile('batch', path)
        if os.path.getsize(path) > META_BYTES:
            return None
        with open(path) as f:
            meta = json.load(f)
        if not isinstance(meta, dict) or not isinstance(meta.get('row'), dict):
            return None
        row, files = meta['row'], meta.get('files')
        if meta.get('rowSum') != _manifest.contentDigest(row) or not isinstance(files, dict):
            return None
        for ext, sum_ in files.items():
            if ext not in ('npz', 'csv', 'png') or _fileDigest(os.path.join(g, key + '.' + ext)) != sum_:
                return None
        r = None
        if row.get('status') == 'ok':
            if 'npz' not in files or 'csv' not in files:
                return None
            r = MssResult.load(os.path.join(g, key + '.npz'))
        return meta, r
    except (OSError, ValueError, KeyError, TypeError, RecursionError):
        return None


def _done(outdir, task, optionsKey):
    """The row and result of a grain already done from the same input (the *task*'s digest, computed only where
    a record is found) with these options, its files as it wrote them (:func:`grainRecord`), or None: the grain
    is made again."""
    found = grainRecord(outdir, task.key)
    if found is None:
        return None
    meta, r = found
    if (meta.get('options') != optionsKey or meta['row'].get('status') == 'failed'
            or meta.get('input') != task.digest):
        return None
    return meta['row'], r


def _digestOf(task):
    """The digest of a grain whose run did not take one (it failed before: a file gone, unreadable): None where
    it cannot be taken either; the grain's failure is recorded all the same (a failure is never reused)."""
    try:
        return task.digest
    except (OSError, ValueError):
        return None


def _store(outdir, key, row, result, optionsKey, digest=None, write=None):
    """Writes a grain's files, then its record (grains/KEY.json, last: a grain without it is not done) with the
    digest of each file and of its row, for the rerun to check (_done). Each file is made in memory and its
    digest taken there: reading every file back cost the batch a tenth of its time. *write* (path, bytes):
    writes a file whole (default: :func:`atomicWrite` here; the batch's :class:`_Files` on a thread)."""
    g = os.path.join(outdir, 'grains')
    sums = {}
    write = write or (lambda path, data: atomicWrite(path, None, 'batch', data))

    def put(ext, data):
        sums[ext] = hashlib.sha256(data).hexdigest()
        write(os.path.join(g, key + '.' + ext), data)
    png = getattr(result, 'png', None)
    if png is not None:
        put('png', png)
        del result.png
    if result is not None:
        put('npz', result._npzBytes())
        put('csv', result._sphereFile('.csv'))
    # the row's text once: its digest is contentDigest's (a row is flat: one piece, the whole text's) and the
    # record holds the same text (two encodings of it were a tenth of the batch's own time a grain)
    text = json.dumps(row, sort_keys=True, default=str)
    record = '{"options": %s, "input": %s, "files": %s, "row": %s, "rowSum": "%s"}' % (
        json.dumps(optionsKey), json.dumps(digest), json.dumps(sums), text, hashlib.sha256(text.encode()).hexdigest())
    write(os.path.join(g, key + '.json'), record.encode())


def _shared(row):
    """*row* with its keys (and status) the one string each of the whole batch: a row unpickled from a worker
    has copies of its own, 1.3 kB a grain (130 MB of a batch of 10^5 grains with workers)."""
    out = {sys.intern(k): v for k, v in row.items()}
    if isinstance(out.get('status'), str):
        out['status'] = sys.intern(out['status'])
    return out


class _InOrder(object):
    """Hands the grains' results on (*keep*(key, result)) in the order their tasks were handed out, holding
    those that come early: local workers finish a few grains out of order, and packed as they came, every
    sphere was copied once more at the end to be put in key order (10^5 grains' spheres are 70 MB). Past HELD
    held (Dask's order is its own), the rest are handed on as they come."""

    HELD = 256

    def __init__(self, keys, keep):
        import collections
        self._next, self._held, self._keep = collections.deque(keys), {}, keep

    def add(self, key, result):
        """A grain's result (None: it has none, failed or skipped: the grains after it go on)."""
        if self._next is None:
            if result is not None:
                self._keep(key, result)
            return
        self._held[key] = result
        while self._next and self._next[0] in self._held:
            k = self._next.popleft()
            r = self._held.pop(k)
            if r is not None:
                self._keep(k, r)
        if len(self._held) > self.HELD:
            self.flush()

    def flush(self):
        """Hands on what is held, in the order it came; from then on every result as it comes."""
        for k, r in self._held.items():
            if r is not None:
                self._keep(k, r)
        self._held, self._next = {}, None


class _Files(object):
    """Writes files whole (:func:`atomicWrite`), in the order they are handed over, on a thread of its own: the
    batch makes a grain's bytes and goes on to the next grain while the disk takes them (the system calls let
    go of the GIL). At most QUEUE files wait; the first error is raised in the batch, at the next file or at
    :meth:`close`, which waits until every file handed over is written. A grain's record comes after its
    files, so an interrupted batch leaves no record of files not written.

    No Python-level lock is taken in the batch's thread (a deque, and a bare lock as the thread's wake-up): a
    Ctrl-C that lands between a ``with lock:``'s acquire and its block leaves the lock held (queue.Queue's), and
    the batch hung in close() after the interrupt."""

    QUEUE = 256

    def __init__(self):
        import _thread
        import collections
        import threading
        self._error, self._items = None, collections.deque()
        self._wake = _thread.allocate_lock()
        self._wake.acquire()  # held while there is nothing to do: released to wake the thread
        self._thread = threading.Thread(target=self._run, name='mss batch files', daemon=True)
        self._thread.start()

    def _run(self):
        while True:
            if not self._items:
                self._wake.acquire(timeout=0.05)  # a wake-up lost to a race costs a twentieth of a second
                continue
            item = self._items.popleft()
            if item is None:
                return
            if self._error is None:  # after an error the rest is dropped: those grains are not done
                try:
                    atomicWrite(item[0], None, 'batch', item[1])
                except BaseException as e:  # noqa: BLE001 (raised in the batch's thread)
                    self._error = e

    def _raise(self):
        if self._error is not None:
            e, self._error = self._error, None
            raise e

    def _put(self, item):
        self._items.append(item)
        try:
            self._wake.release()
        except RuntimeError:
            pass  # awake already

    def write(self, path, data):
        self._raise()
        while len(self._items) >= self.QUEUE and self._thread.is_alive():
            time.sleep(0.001)  # the disk is behind: the batch waits, its memory stays bounded
        self._put((path, data))

    def close(self):
        self._put(None)
        self._thread.join()
        self._raise()


@optionTable.documented('batch')
def batch(inputs, outdir=None, workers=None, scheduler=None, minVoxels=0, excludeBorder=False, labels=None,
          voxelSize=None, origin=None, progress=True, previews=False, security=None, density=1000.0, young=1e9,
          format=None, segment=False, segmentH=None, segmentMarkers=None, connectTimeout=5.0, **options):
    """Generates every grain of a labelled volume (or of several files) and, with *outdir*, writes the
    assembly, as ``mss batch`` does (the options are the same, spelled for Python).

    :param inputs: a labelled volume (.npy or .tif file, or an integer array; 0 is background), or mesh and
        volume files and folders of them, one grain each
    :param outdir: the output folder (a rerun resumes in it); None: nothing is written
    :param labels: only these labels of a labelled volume, a list of integers
    :param bool progress: a progress bar on a terminal, a line per grain otherwise
    :param bool segment: *inputs* is a binary scan: cut it into grains first (:func:`yade_mss.grains.segmentScan`;
        segments under *minVoxels* are dropped, not grains)
    :param float segmentH: with *segment*: the markers' fixed height, voxels (default: chosen from the grains'
        own size)
    :param segmentMarkers: with *segment*: a label volume (or its .npy file) of markers of the user's own
    :param security: a ``distributed.Security`` for a TLS scheduler (``tls://``); anyone who can reach a
        scheduler without it runs code as its workers (Dask moves pickles)
    OPTIONS
    :param options: :func:`generate`'s keywords (nSpheres, dice, eta, rMin, resolution for meshes, clip, ...)
    :return: :class:`Batch`
    """
    gen, = split('batch', options, [o for o in GENERATE_OPTIONS if o not in ('voxelSize', 'origin', 'label',
                                                                             'threads')])
    inputs = _checkedInputs(inputs)
    if outdir is not None and not isinstance(outdir, (str, bytes, os.PathLike)):
        raise TypeError('batch: outdir must be a folder path, got %s' % type(outdir).__name__)
    checkScheduler('batch', scheduler, security)
    if not any(gen.get(k) for k in ('nSpheres', 'eta', 'dice', 'rMin', 'rMinVoxels')):
        raise ValueError('batch: give at least one termination criterion (--spheres, --eta, --dice, --rmin or '
                         '--rmin-voxels; nSpheres, eta, dice, rMin or rMinVoxels in Python): without one every '
                         'grain would fail')
    segment, excludeBorder, previews, progress = (flag('batch', n, v) for n, v in (
        ('segment', segment), ('excludeBorder', excludeBorder), ('previews', previews), ('progress', progress)))
    minVoxels = integer('batch', 'minVoxels', minVoxels, 0, None)
    if voxelSize is not None and number('batch', 'voxelSize', voxelSize) <= 0:
        raise ValueError('batch: voxelSize must be > 0 (the voxel edge in metres), got %r' % (voxelSize,))
    if origin is not None:
        origin = tuple(vector3('batch', 'origin', origin))
    if labels is not None:
        if not isinstance(labels, (list, tuple)):
            raise TypeError('batch: labels must be a list of integers, got %r' % (labels,))
        labels = [integer('batch', 'labels', x, 1, None) for x in labels]
    if workers is None:  # inside YADE one process: spawning children of the yade launcher does not work
        workers = 1 if 'yade' in sys.modules else freeCores()
    workers = integer('batch', 'workers', workers, 1, 1024)
    density, young, connectTimeout = (optionTable.check('batch', 'batch', n, v) for n, v in (
        ('density', density), ('young', young), ('connectTimeout', connectTimeout)))
    if format is not None:
        format = optionTable.check('batch', 'batch', 'format', format)
        if outdir is None:
            raise ValueError('batch: format %r writes templates into the output folder: give outdir' % format)
    t0 = time.perf_counter()
    if outdir is not None:
        _refuseOverInputs(inputs, outdir)
    # one batch a folder: a second is refused at once, not left to mix its grains with the first's
    with folderLock('batch', outdir) if outdir is not None else contextlib.nullcontext():
        runKey = None
        if outdir is not None:
            runKey = _runKey(inputs, gen, {'voxelSize': voxelSize, 'origin': origin, 'minVoxels': minVoxels,
                                           'excludeBorder': excludeBorder, 'labels': labels, 'previews': previews,
                                           'density': density, 'young': young, 'format': format, 'segment': segment,
                                           'segmentH': segmentH,
                                           'segmentMarkers': _fileKey(segmentMarkers)})
            state = _manifest.finished(outdir, runKey)
            if state is not None:
                out = _upToDate(outdir, state, time.perf_counter() - t0)
                if progress:
                    print('batch: %s is up to date (its inputs, options and files are those of its finished run): '
                          'nothing to do\n%s' % (outdir, _report.summary(out, len(out.rows), density, young)),
                          flush=True)
                return out
            _manifest.forget(outdir)
        segmented = None
        if segment or segmentH is not None or segmentMarkers is not None:
            if segmentH is not None:
                segmentH = optionTable.check('batch', 'batch', 'segmentH', segmentH)
            if not segment:
                raise ValueError('batch: segmentH and segmentMarkers apply with segment (a binary scan to cut into '
                                 'grains)')
            with slowPhase('batch: segmenting the binary scan', progress):
                inputs, segmented = _segmented(inputs, outdir, segmentH, gen.get('memoryLimit'), segmentMarkers,
                                               minVoxels)
        scan = {}
        tasks, skipped, key, found = makeTasks(inputs, gen, voxelSize, origin, minVoxels, excludeBorder, labels,
                                               scan)
        releaseFreed()  # the contact search's tables and slabs
        if segmented is not None:
            key = _optionsKey(key, {'segment': segmentH, 'segmentMarkers': _fileKey(segmentMarkers)})
        if format == 'liggghts':
            if len(tasks) > MAX_TEMPLATES:  # said before the grains are generated, not after
                raise ValueError('batch: %d grains: LIGGGHTS templates are numbered by 32-bit seeds, at most %d'
                                 % (len(tasks), MAX_TEMPLATES))
        out = Batch()
        out.segmented = segmented
        if outdir is not None:
            out.storing()
            os.makedirs(os.path.join(outdir, 'grains'), exist_ok=True)
            for k, row in skipped.items():
                _store(outdir, k, row, None, key)
        out.rows.update(skipped)
        todo = []
        for t in tasks:
            prior = _done(outdir, t, key) if outdir is not None else None
            if prior is None:
                todo.append(t)
            else:
                out.rows[t.key], r = prior
                if r is not None:
                    out.keep(t.key, r)
        total, already = len(tasks) + len(skipped), len(tasks) - len(todo)
        bar = None
        if progress and sys.stderr.isatty():
            from tqdm import tqdm
            bar = tqdm(total=len(todo), unit='grain', desc='mss batch')
        elif progress:
            print('batch: %d grains, %d done before, %d skipped, %d to generate'
                  % (total, already, len(skipped), len(todo)), flush=True)
        # no idle processes for few grains
        # local workers are forked with the list (and the mapped scan): each cuts its grains' crops itself
        run, close = _executor(min(workers, max(1, len(todo))), scheduler, security, connectTimeout, todo)
        n = made = 0  # made: the grains this run generated (ok), not those it tried
        byKey = {t.key: t for t in todo}
        inOrder = _InOrder([t.key for t in todo], out.keep)
        files = _Files() if outdir is not None else None
        try:
            for k, row, r in run(todo):
                digest, task = row.pop(DIGEST, None), byKey.pop(k)
                row = _shared(row)
                # a grain whose worker died is not the grain's failure: nothing is written for it (the pool's stop,
                # an interrupted batch's workers ending before the batch, must not look like a finished grain)
                if outdir is not None and not row['message'].startswith(WORKER_DIED):
                    _store(outdir, k, row, r, key, digest or _digestOf(task), files.write)
                task._digest = None  # written: not held for 10^5 grains
                out.rows[k] = row
                inOrder.add(k, r)
                n += 1
                made += row['status'] == 'ok'
                if n % RELEASE_EVERY == 0:
                    releaseFreed()  # the grains' results and crops come and go: the heap's holes given back
                if bar is not None:
                    bar.update(1)
                elif progress:
                    balls = row.get('contact_spheres') or 0  # --spheres N is N: the contact balls said apart
                    print('[%*d/%d] %-12s %-7s %3s spheres%s  D %-8s %s' % (
                        len(str(len(todo))), n, len(todo), k, row['status'],
                        row['spheres'] - balls if balls else row['spheres'],
                        ' + %d contact ball%s' % (balls, '' if balls == 1 else 's') if balls else '',
                        '%.4f' % row['dice'] if row['dice'] != '' else '-', row['message'][:80]), flush=True)
        finally:
            close()
            if files is not None:
                files.close()  # every grain's files written (or the first error raised) before the outputs
            if bar is not None:
                bar.close()
        inOrder.flush()
        out.generated, out.reused = made, already
        out.rows = dict(sorted(out.rows.items(), key=lambda kv: _order(kv[0])))
        out.finish(outdir, _order)
        h = (1.0 if voxelSize is None else float(voxelSize)) * float(gen.get('scale') or 1.0)  # as makeTasks read it
        if found is not None:  # a labelled volume: its voxel edge, said in the summary with its unit
            out.voxelSize, out.voxelSizeGiven = h, voxelSize is not None or gen.get('scale') not in (None, 1.0)
        out.scanBox = scan.get('box')
        out.flagAt = _report.flagLine(gen)
        # the report's pictures need only the rows: drawn in a child meanwhile, on the core the workers left
        drawing = (alongside(lambda: _report.drawPictures(outdir, out),
                             'batch: %s' % os.path.join(outdir, 'report_*.png'))
                   if outdir is not None else contextlib.nullcontext())
        with drawing:
            with slowPhase('batch: the contacts of %d grains in the assembly' % len(out.results), progress):
                _report.keptContacts(out, found, h)
                _report.annotate(out, gen, density, young)
            releaseFreed()  # the grains' results as they came, the pairs' arrays
            if outdir is not None:
                if previews:
                    with slowPhase('batch: drawing the previews', progress):
                        _report.drawPreviews(outdir, out, {t.key: t for t in tasks})
                out.seconds = time.perf_counter() - t0
                with slowPhase('batch: writing the assembly, grains.csv and the report', progress):
                    _report.writeOutputs(outdir, out, density, young)
                    if format is not None:
                        writeTemplates(outdir, out, format, density)
        out.seconds = time.perf_counter() - t0
        if outdir is not None and not out.failed:
            _manifest.write(outdir, runKey, _state(out), _atomic)
        if progress:
            print(_report.summary(out, total, density, young), flush=True)
        return out


def _checkedInputs(inputs):
    """*inputs* as a list of paths, or the integer array (one path alone is a list of one, not its characters)."""
    if isinstance(inputs, np.ndarray):
        if inputs.ndim != 3:
            raise ValueError('batch: a labelled volume must be a 3-D array, got %d-D' % inputs.ndim)
        return inputs
    if isinstance(inputs, (str, bytes, os.PathLike)):
        return [inputs]
    if not isinstance(inputs, (list, tuple)) or not inputs:
        raise TypeError('batch: inputs must be a file or folder path, a list of them, or a labelled volume (an '
                        'integer array), got %r' % (inputs,))
    for p in inputs:
        if not isinstance(p, (str, bytes, os.PathLike)):
            raise TypeError('batch: inputs must be file or folder paths, got %r' % (p,))
    return list(inputs)


OUTPUTS = ('labels.npy', 'grains.csv', 'assembly.txt', 'assembly.vtk', 'contacts.csv', 'report.html',
           'report_distributions.png', 'report_segmentation.png', _manifest.NAME, 'placements.csv')


def _refuseOverInputs(inputs, outdir):
    """Before any work: no output folder (or folder in it) that is a link however the path is spelled, no output
    or file in grains/ or templates/ that is a link or not a regular file, no output that is an input, no input
    among the grains' files, no output folder that is an input folder."""
    outdir = os.fspath(outdir)
    refuseLinkedFolders('batch', [outdir] + [os.path.join(outdir, d) for d in ('grains', 'templates')])
    if os.path.lexists(outdir) and not os.path.isdir(outdir):
        raise ValueError('batch: the output folder %s exists and is not a folder' % outdir)
    for n in OUTPUTS:
        path = os.path.join(outdir, n)
        if os.path.lexists(path) and not stat.S_ISREG(os.lstat(path).st_mode):
            raise ValueError('batch: OUT/%s (%s) exists and is not a regular file (a link, folder or device): the '
                             'batch would not write it; remove it or name another output folder' % (n, path))
    for d in ('grains', 'templates'):
        folder = os.path.join(outdir, d)
        if not os.path.lexists(folder):
            continue
        if not os.path.isdir(folder):
            raise ValueError('batch: OUT/%s (%s) exists and is not a folder: remove it or name another output '
                             'folder' % (d, folder))
        with os.scandir(folder) as entries:
            for e in entries:
                if not e.is_file(follow_symlinks=False) and not e.name.startswith('.'):
                    raise ValueError('batch: OUT/%s/%s is a link or not a regular file: the batch writes only its '
                                     'own files there; remove it or name another output folder' % (d, e.name))
    if isinstance(inputs, np.ndarray):
        return
    here = os.path.realpath(outdir)
    for d in inputs:
        if os.path.isdir(d) and os.path.realpath(d) == here:
            raise ValueError('batch: the output folder %s is the input folder %s: its outputs would become inputs '
                             'of the next run; name another output folder' % (outdir, os.fspath(d)))
    files = [os.fspath(f) for f in inputs if os.path.isfile(f)]
    for d in inputs:
        if os.path.isdir(d):
            files += [os.path.join(d, f) for f in os.listdir(d)]
    refuseOverInputs('batch', [('OUT/' + n, os.path.join(outdir, n)) for n in OUTPUTS], files)
    grains = os.path.realpath(os.path.join(outdir, 'grains'))
    for f in files:
        if os.path.dirname(os.path.realpath(f)) == grains:
            raise ValueError('batch: the input %s lies in the output folder\'s grains/, which the batch writes: move '
                             'it out or name another output folder' % f)


def _fileKey(markers):
    """What a run key holds of the user's markers: a file's path and size and time, an array's digest."""
    if markers is None:
        return None
    if not isinstance(markers, (np.ndarray, str, os.PathLike)):
        raise TypeError('batch: segmentMarkers must be a label volume or its .npy file, got %r' % (markers,))
    if isinstance(markers, np.ndarray):
        return hashlib.sha256(np.ascontiguousarray(markers).tobytes()).hexdigest()
    st = os.stat(os.fspath(markers))
    return [os.path.abspath(os.fspath(markers)), st.st_size, st.st_mtime_ns]


def _segmented(inputs, outdir, h, memoryLimit=None, markers=None, minVoxels=0):
    """A binary scan (one volume file or array) cut into grains (:func:`segmentScan`; *markers*: a label volume
    or its .npy file, seeds of the user's own), its labels written to OUTDIR/labels.npy: (the label array, what
    the report shows of it: {'file', 'grains', 'h', 'info' (segmentScan's), 'sizes' (each grain's voxels),
    'binary' and 'labels': the middle section across z})."""
    if isinstance(inputs, np.ndarray):
        vol, name = inputs, '(array)'
    else:
        files = _inputs(inputs)
        if len(files) != 1 or os.path.splitext(files[0])[1].lower() not in VOLUME_EXT:
            raise ValueError('batch: segment applies to one volume file (a binary scan), got %s'
                             % ', '.join(files[:3]))
        vol, name = readVolume(files[0]), files[0]
    checkLabelled(vol, name, segment=True, memoryLimit=memoryLimit)
    if markers is not None and not isinstance(markers, np.ndarray):
        if not isinstance(markers, (str, os.PathLike)):
            raise TypeError('batch: segmentMarkers must be a label volume or its .npy file, got %r' % (markers,))
        markers = readVolume(markers)
    labels, info = segmentScan(vol, h, markers, minVoxels, memoryLimit)
    if info['grains'] == 0:  # said here: the volume is not empty, its pieces were all dropped
        raise ValueError('batch: %s: segmenting left no grain: %d specks (pieces under %d voxels) and %d segments '
                         'under --min-voxels %d were dropped' % (name, info['specks'], SPECK_VOXELS, info['small'],
                                                                 minVoxels))
    path = None
    if outdir is not None:
        os.makedirs(outdir, exist_ok=True)
        path = os.path.join(outdir, 'labels.npy')
        _atomic(path, lambda p: np.save(p, labels))
    z = labels.shape[2] // 2
    return labels, {'file': path, 'grains': int(labels.max()), 'h': h, 'info': info,
                    'sizes': np.bincount(labels.ravel())[1:].tolist(), 'binary': np.asarray(vol[:, :, z]) != 0,
                    'labels': labels[:, :, z].copy(), 'z': z}


def _order(key):
    kind, _, rest = key.partition('_')
    return (kind, int(rest) if rest.isdigit() else 0, rest)
