"""yade-mss: multi-sphere (MSS) clumps for YADE, from a triangle mesh or a voxel volume.

The generator (C++, module :mod:`yade_mss._mss`) works in any Python with numpy; the functions that build
bodies need a running YADE (``yade -n -x script.py``).

Quick start, in a YADE script::

    from yade_mss import mssClump
    clumpId, memberIds = mssClump('grain.stl', nSpheres=30)

Units are those of the input file. Densities come from the material, as in :yref:`utils.sphere`.

Modules: ``_results`` (results, sphere files), ``_sources`` (meshes, voxels, their mass properties),
``_generate`` (generation, scoring), ``_loads`` (the sums that make YADE clumps exact, numpy only),
``_clumps`` (YADE clumps), ``_records`` (their records), ``_restore`` (exact properties back),
``_clumpfiles`` (clump sets to and from files), ``_templates`` (templates, packings),
``_specimen`` (labelled volumes, synthetic specimens), ``_batch`` (mss batch), ``_assembly`` (specimens in YADE),
``_pictures`` (mss preview, mss curve), ``_ochart`` (mss ochart: the clumps' cost), ``_spheropolygon`` (2-D: spheropolygons, the O-chart), ``_breakage`` (grains that break: mssSplit, MssBreakage).
"""

import os as _os


def _runtimeLoaded():
    """Whether the OpenMP runtime is in the process already (YADE loads it): then it read its wait policy at
    its start, and setting one now changes nothing."""
    try:
        with open('/proc/self/maps') as f:
            return 'libgomp' in f.read()
    except OSError:
        return False


# OpenMP threads that spin collapse when the cores are shared (YADE, a batch): wait passively unless the user
# chose. Effective when the OpenMP runtime loads with our module (plain python3). Inside YADE, which loads it
# first with waiters that spin, the generator is told so (MSS_OMP_SPINNING): it then takes the cores other
# processes leave free, not all of them (under a load of 8 on 2 cores, a default generation took 3-7 times as
# long as one thread).
if (_runtimeLoaded() and _os.environ.get('OMP_WAIT_POLICY', '').lower() != 'passive'
        and 'GOMP_SPINCOUNT' not in _os.environ):
    _os.environ['MSS_OMP_SPINNING'] = '1'
_os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')

from ._results import MassProperties, MssResult, readSpheres  # noqa: E402
from ._sources import massProperties  # noqa: E402
from ._generate import compareMany, generate, score  # noqa: E402
from ._clumps import mssClump, porosity, totalMass  # noqa: E402
from ._restore import restoreClumpProperties  # noqa: E402
from ._clumpfiles import readClumps, writeClumps  # noqa: E402
from ._templates import MssTemplate, mssClumpCloud, mssReplaceByClumps, mssTemplate  # noqa: E402
from ._batch import batch  # noqa: E402
from ._assembly import mssAssembly  # noqa: E402
from ._specimen import findContacts, packedSpecimen, regions, syntheticSpecimen, voronoiBall  # noqa: E402
from ._spheropolygon import boundaryRegions, ochart, spheropolygon, spheropolygons  # noqa: E402
from ._ochart import clumpOchart  # noqa: E402
from ._breakage import MssBreakage, breakageLog, breakagePotential, grainSizes, mssSplit, relativeBreakage  # noqa: E402
from . import _mss  # noqa: F401 (the C++ module, for tests and advanced use)

__all__ = ['MassProperties', 'MssResult', 'generate', 'readSpheres', 'score', 'compareMany', 'massProperties',
           'mssClump', 'restoreClumpProperties', 'totalMass', 'porosity', 'writeClumps', 'readClumps',
           'mssTemplate', 'MssTemplate', 'mssClumpCloud', 'mssReplaceByClumps', 'batch', 'mssAssembly', 'regions',
           'syntheticSpecimen', 'packedSpecimen', 'voronoiBall', 'findContacts', 'spheropolygon', 'spheropolygons',
           'boundaryRegions', 'ochart', 'clumpOchart', 'mssSplit', 'MssBreakage', 'breakageLog', 'grainSizes',
           'breakagePotential', 'relativeBreakage']
