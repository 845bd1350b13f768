"""Pictures, drawn with matplotlib's Agg backend (no display): a clump against its grain (:func:`preview`), D
and time against the sphere count (:func:`curve`), the clumps' cost chart (:func:`clumpOchart`) and an
assembly seen from the side (:func:`sideView`).
"""

from ._assembly import sideView
from ._curve import counts, curve
from ._ochart import cheapest, clumpOchart, pareto
from ._preview import grainVoxels, preview, pyplot, save

__all__ = ['sideView', 'counts', 'curve', 'cheapest', 'clumpOchart', 'pareto', 'grainVoxels', 'preview', 'pyplot', 'save']
