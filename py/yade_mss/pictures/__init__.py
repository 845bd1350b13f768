"""Pictures, drawn with matplotlib's Agg backend (no display): a clump against its grain (:func:`preview`), D
and time against the sphere count (:func:`curve`) and the clumps' cost chart (:func:`clumpOchart`).
"""

from ._curve import counts, curve
from ._ochart import cheapest, clumpOchart, pareto
from ._preview import grainVoxels, preview, pyplot, save

__all__ = ['counts', 'curve', 'cheapest', 'clumpOchart', 'pareto', 'grainVoxels', 'preview', 'pyplot', 'save']
