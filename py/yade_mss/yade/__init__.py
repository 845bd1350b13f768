"""YADE: clumps built from generated grains with the grains' exact mass properties (:func:`mssClump`), their
records and restoring (:func:`restoreClumpProperties`), clump files, templates and clouds for packings, and
grains that break. The only layer that imports YADE (``yade``, ``yade.wrapper``), and only inside functions, so
that the package imports in a plain python3 too.
"""

from ._breakage import (MssBreakage, breakageLog, breakagePotential, contactsByClump, grainSizes, mssSplit,
                        opposingPair, relativeBreakage, step as breakageStep, weibullStrength)
from ._clumpfiles import readClumps, writeClumps
from ._clumps import (SCAN_BOX_TAG, bodyOptions, buildClump, mssClump, porosity, requireVoxelSize, rotation, totalMass,
                      yadeModules)
from ._loads import memberLoads, sumsAsYade, tiltedShares
from ._restore import restoreClumpProperties
from ._stiffness import MARK as GRAIN_STIFFNESS_MARK, contactStiffnessEngine, contactStiffnessStep
from ._templates import MssTemplate, mssClumpCloud, mssReplaceByClumps, mssTemplate

__all__ = ['MssBreakage', 'breakageLog', 'breakagePotential', 'contactsByClump', 'grainSizes', 'mssSplit',
           'opposingPair', 'relativeBreakage', 'breakageStep', 'weibullStrength', 'readClumps', 'writeClumps',
           'SCAN_BOX_TAG', 'bodyOptions', 'buildClump', 'mssClump', 'porosity', 'requireVoxelSize', 'rotation',
           'totalMass', 'yadeModules',
           'memberLoads', 'sumsAsYade', 'tiltedShares', 'restoreClumpProperties', 'MssTemplate', 'mssClumpCloud',
           'mssReplaceByClumps', 'mssTemplate', 'GRAIN_STIFFNESS_MARK', 'contactStiffnessEngine',
           'contactStiffnessStep']
