"""Specimens: a CT scan (labelled or binary) or a folder of grains to a DEM assembly, locally or on Dask
(:func:`batch`), with its report; the assembly in YADE (:func:`mssAssembly`, through the yade layer's
functions); synthetic specimens made as real pipelines make them, for tests and tutorials.
"""

from ._assembly import Assembly, mssAssembly
from ._batch import Batch, GrainTask, batch, checkLabelled, grainRecord, makeTasks, runGrain
from ._manifest import read as readManifest
from ._pools import checkScheduler, clusterSecurity, freeCores
from ._synthetic import bestOverlap, packedSpecimen, porousScan, syntheticSpecimen, voronoiBall

__all__ = ['Assembly', 'mssAssembly', 'Batch', 'GrainTask', 'batch', 'checkLabelled', 'checkScheduler',
           'clusterSecurity', 'freeCores',
           'grainRecord', 'makeTasks', 'readManifest', 'runGrain', 'bestOverlap', 'packedSpecimen', 'porousScan',
           'syntheticSpecimen', 'voronoiBall']
