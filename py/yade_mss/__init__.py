"""yade-mss: multi-sphere (MSS) clumps for YADE, from a triangle mesh or a voxel volume.

The generator (C++, module :mod:`yade_mss._mss`) works in any Python with numpy; the functions that build
bodies need a running YADE (``yade -n -x script.py``).

Quick start, in a YADE script::

    from yade_mss import mssClump
    clumpId, memberIds = mssClump('grain.stl', nSpheres=30)

Units are those of the input file. Densities come from the material, as in :yref:`utils.sphere`.

Modules: ``_results`` (results, sphere files), ``_sources`` (meshes, voxels, their mass properties),
``_generate`` (generation, scoring), ``_loads`` (the sums that make YADE clumps exact, numpy only),
``_clumps`` (YADE clumps), ``_clumpfiles`` (clump sets to and from files), ``_templates`` (templates, packings),
``_specimen`` (labelled volumes, synthetic specimens), ``_batch`` (mss batch), ``_assembly`` (specimens in YADE),
``_pictures`` (mss preview, mss curve), ``_spheropolygon`` (2-D: spheropolygons, the O-chart).
"""

from ._results import MassProperties, MssResult, readSpheres
from ._sources import massProperties
from ._generate import compareMany, generate, score
from ._clumps import mssClump, restoreClumpProperties
from ._clumpfiles import readClumps, writeClumps
from ._templates import MssTemplate, mssClumpCloud, mssReplaceByClumps, mssTemplate
from ._batch import batch
from ._assembly import mssAssembly
from ._specimen import regions, syntheticSpecimen
from ._spheropolygon import ochart, spheropolygon, spheropolygons
from . import _mss  # noqa: F401 (the C++ module, for tests and advanced use)

__all__ = ['MassProperties', 'MssResult', 'generate', 'readSpheres', 'score', 'compareMany', 'massProperties', 'mssClump',
           'restoreClumpProperties', 'writeClumps', 'readClumps', 'mssTemplate', 'MssTemplate', 'mssClumpCloud',
           'mssReplaceByClumps', 'batch', 'mssAssembly', 'regions', 'syntheticSpecimen',
           'spheropolygon', 'spheropolygons', 'ochart']
