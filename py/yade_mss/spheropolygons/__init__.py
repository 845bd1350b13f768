"""Spheropolygons from 2-D particle images (the second paper): the fit (Algorithm 1, in C++), the boundary's
regions, the O-chart (eq. 5-8) and their pictures.
"""

from ._spheropolygon import (boundaryRegions, cow, ochart, previewSpheropolygon, rasterizeNumpy, readImage,
                             spheropolygon, spheropolygons)

__all__ = ['boundaryRegions', 'cow', 'ochart', 'previewSpheropolygon', 'rasterizeNumpy', 'readImage',
           'spheropolygon', 'spheropolygons']
