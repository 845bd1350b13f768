"""What a triaxial study is made of: its inputs (a grain file, a labelled volume, a folder of grains, a finished
``mss batch`` folder, or another generator's sphere file with its grain) as grains, each generated at any
sphere count (numpy and the generator only: no YADE here)."""

import os

import numpy as np

from ..base import readNpy
from ..grains import MssResult, generate, massProperties, readSpheres, regions
from ..specimens import readManifest
from ..yade import requireVoxelSize

MESHES = ('.stl', '.obj', '.off', '.ply')
VOLUMES = ('.npy', '.tif', '.tiff')
SPHERE_FILES = ('.csv', '.txt')


class Grain(object):
    """One grain of a study: *name*, its *weight* (share of the specimen's grains), and either a *source* to
    generate from (with *label* of a labelled volume) or *fixed* spheres (an :class:`MssResult` of another
    generator, the same at every count)."""

    def __init__(self, name, source=None, label=None, fixed=None, weight=1.0):
        self.name, self.source, self.label, self.fixed, self.weight = name, source, label, fixed, weight

    def at(self, n, gen):
        """The grain's spheres at count *n* (*gen*: the other generation keywords)."""
        if self.fixed is not None:
            return self.fixed
        extra = dict(label=self.label, contacts=False) if self.label is not None else {}
        return generate(self.source, nSpheres=int(n), **dict(gen, **extra))


def _isVolume(path):
    return os.path.splitext(path)[1].lower() in VOLUMES


def _volumeGrains(path, gen):
    """A volume file: one grain, or each label of a labelled one (the scan's grains, each once)."""
    requireVoxelSize('triaxial', path, gen)
    if path.lower().endswith('.npy'):
        a = readNpy('triaxial', path, mmap=True)
        if a.dtype != bool and a.ndim == 3:
            found = regions(np.asarray(a))
            if len(found) > 1:
                return [Grain('%s label %d' % (os.path.basename(path), r.label), path, label=int(r.label))
                        for r in found]
    return [Grain(os.path.basename(path), path)]


def _folderGrains(folder, gen):
    names = sorted(f for f in os.listdir(folder) if os.path.splitext(f)[1].lower() in MESHES + VOLUMES)
    if not names:
        raise ValueError('triaxial: %s holds no grain file (%s)' % (folder, ' '.join(MESHES + VOLUMES)))
    out = []
    for n in names:
        p = os.path.join(folder, n)
        out += _volumeGrains(p, gen) if _isVolume(p) else [Grain(n, p)]
    return out


def _batchGrains(folder, gen):
    """A finished ``mss batch`` folder: the grains it generated (grains/*.npz), regenerated from its scan at
    each count with its voxel size and origin, in the scan's proportions (each grain once) and sizes."""
    manifest = readManifest(folder)
    if manifest is None:
        raise ValueError('triaxial: %s/batch.json is not the manifest its batch wrote (edited, unreadable or of an '
                         'older version): run the batch again' % folder)
    key = manifest.get('key')
    files = ((key or {}).get('inputs') or {}).get('files') if isinstance(key, dict) else None
    done = sorted(n[:-4] for n in os.listdir(os.path.join(folder, 'grains')) if n.endswith('.npz'))
    if not isinstance(files, list) or len(files) != 1 or not done:
        raise ValueError('triaxial: %s: not a finished batch of one labelled volume (batch.json names its scan, '
                         'grains/ holds its results); give the grain files or their folder instead' % folder)
    volume = files[0][0]
    if not os.path.isfile(volume):
        raise ValueError('triaxial: %s: the batch\'s scan %s is gone: it is needed to generate its grains again'
                         % (folder, volume))
    b = key.get('batch', {})
    for k in ('voxelSize', 'origin'):
        if b.get(k) is not None and gen.get(k) is None:
            gen[k] = b[k]
    requireVoxelSize('triaxial', volume, gen)
    out = []
    for name in done:
        if not name.startswith('label_') or not name[6:].isdigit():
            raise ValueError('triaxial: %s/grains/%s.npz: not a labelled grain\'s result' % (folder, name))
        out.append(Grain(name, volume, label=int(name[6:])))
    return out


def _sphereFileGrain(path, grain, gen):
    """Another generator's spheres standing for *grain*: the grain gives the exact mass properties."""
    if grain is None:
        raise ValueError('triaxial: %s is a sphere file: name the grain it stands for (grain=..., --grain) for its '
                         'exact mass' % path)
    r = readSpheres(path)
    s = gen.get('scale') or 1.0
    if _isVolume(grain):
        requireVoxelSize('triaxial', grain, gen)
    m = massProperties(grain, voxelSize=gen.get('voxelSize'), origin=gen.get('origin'))
    fixed = MssResult(r.centers * s, r.radii * s, metrics=dict(spheres=len(r.radii)),
                      targetMass=m.transformed(scale=s),
                      source=os.path.basename(path))
    off = np.linalg.norm(fixed.unionMass().centroid - fixed.targetMass.centroid)
    if off > 0.2 * fixed.boundingRadius():
        raise ValueError('triaxial: %s: its spheres lie %.3g from the grain\'s centre of mass (%s), beyond a fifth '
                         'of their bounding radius: they are in another frame; align them to the grain first'
                         % (path, off, grain))
    return Grain(os.path.basename(path), fixed=fixed)


def resolve(inputs, grain, gen):
    """The study's grains from *inputs* (paths), with generation keywords *gen* (voxelSize and origin may be
    filled in from a batch's manifest)."""
    if isinstance(inputs, (str, bytes, os.PathLike)):
        inputs = [inputs]
    if not isinstance(inputs, (list, tuple)) or not inputs:
        raise TypeError('triaxial: inputs must be a path or a list of paths, got %r' % (inputs,))
    out = []
    for p in inputs:
        if not isinstance(p, (str, os.PathLike)):
            raise TypeError('triaxial: an input must be a path, got %r' % (p,))
        p = os.fspath(p)
        ext = os.path.splitext(p)[1].lower()
        if os.path.isdir(p):
            out += _batchGrains(p, gen) if os.path.isfile(os.path.join(p, 'batch.json')) else _folderGrains(p, gen)
        elif not os.path.isfile(p):
            raise ValueError('triaxial: %s: no such file or folder' % p)
        elif ext in SPHERE_FILES:
            out.append(_sphereFileGrain(p, grain, gen))
        elif ext in VOLUMES:
            out += _volumeGrains(p, gen)
        elif ext in MESHES:
            out.append(Grain(os.path.basename(p), p))
        else:
            raise ValueError('triaxial: %s: not a grain (%s), a sphere file (%s) or a folder'
                             % (p, ' '.join(MESHES + VOLUMES), ' '.join(SPHERE_FILES)))
    if grain is not None and not any(g.fixed is not None for g in out):
        raise ValueError('triaxial: grain is for an input that is a sphere file; none is')
    return out
