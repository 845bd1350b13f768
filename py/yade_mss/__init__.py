"""yade-mss: multi-sphere (MSS) clumps for YADE, from a triangle mesh or a voxel volume.

The generator (C++, module :mod:`yade_mss._mss`) works in any Python with numpy; the functions that build
bodies need a running YADE (``yade -n -x script.py``).

Quick start, in a YADE script::

    from yade_mss import mssClump
    clumpId, memberIds = mssClump('grain.stl', nSpheres=30)

Units are those of the input file. Densities come from the material, as in :yref:`utils.sphere`.

The package is in layers, each a sub-package importing only those below it (docs/guide/architecture.rst):
``base`` (checks, files, the work limit), ``grains`` (sources, options, generation, results, scan contacts),
``exports``, ``pictures`` and ``spheropolygons``, ``yade`` (the only layer that imports YADE), ``specimens``
(batch, assembly, synthetic specimens), ``studies`` (the triaxial test and the sphere-count study) and ``cli``. The names below are the user's API.
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

from .grains import (MassProperties, MssResult, compareMany, findContacts, generate, massProperties,  # noqa: E402
                     readSpheres, regions, score)
from .pictures import clumpOchart  # noqa: E402
from .spheropolygons import boundaryRegions, ochart, spheropolygon, spheropolygons  # noqa: E402
from .yade import (MssBreakage, MssTemplate, breakageLog, breakagePotential, contactStiffnessEngine,  # noqa: E402
                   grainSizes, mssClump,
                   mssClumpCloud, mssReplaceByClumps, mssSplit, mssTemplate, porosity, readClumps, relativeBreakage,
                   restoreClumpProperties, totalMass, writeClumps)
from .specimens import batch, mssAssembly, packedSpecimen, porousScan, syntheticSpecimen, voronoiBall  # noqa: E402
from .studies import TriaxialResult, triaxial, triaxialStudy  # noqa: E402
from . import _mss  # noqa: E402,F401 (the C++ module, for tests and advanced use)

__version__ = _mss.version()  # one version, the CMake project's: the library's, mss --version's, the manual's

__all__ = ['MassProperties', 'MssResult', 'generate', 'readSpheres', 'score', 'compareMany', 'massProperties',
           'mssClump', 'restoreClumpProperties', 'totalMass', 'porosity', 'writeClumps', 'readClumps',
           'mssTemplate', 'MssTemplate', 'mssClumpCloud', 'mssReplaceByClumps', 'batch', 'mssAssembly', 'regions',
           'syntheticSpecimen', 'packedSpecimen', 'porousScan', 'voronoiBall', 'findContacts', 'spheropolygon', 'spheropolygons',
           'boundaryRegions', 'ochart', 'clumpOchart', 'mssSplit', 'MssBreakage', 'breakageLog', 'grainSizes',
           'breakagePotential', 'relativeBreakage', 'contactStiffnessEngine', 'triaxial', 'triaxialStudy', 'TriaxialResult']
