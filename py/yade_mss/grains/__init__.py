"""Grains: what a grain is read from (meshes, voxel volumes, labelled scans), the option table, generation and
scoring (MSS paper, sections 2-3, eq. 27), the results, and the contacts of a scan. numpy and the C++ module
only: nothing here imports YADE or matplotlib.

The user's names are re-exported by :mod:`yade_mss`; the rest is this layer's API for the layers above.
"""

from . import _options as optionTable
from ._contacts import NEARBY_GAP, ContactIndex, ScanContacts, contactPoints, contactsByLabel, findContacts, scanContacts
from ._generate import GENERATE_OPTIONS, compareMany, generate, generateWith, score
from ._results import TEMPLATE_EXTENSIONS, ClumpSurface, MassProperties, MssResult, readSpheres
from ._sources import MESH_EXT, Mesh, checkedPlane, flatArray, massProperties, readGrain
from ._segment import SPECK_VOXELS, segmentBinary, segmentScan
from ._volumes import (VOLUME_EXT, Region, binaryValue, pieces, readVolume, regions, separated, slabVoxels,
                       valueRange)

__all__ = ['optionTable', 'NEARBY_GAP', 'ContactIndex', 'ScanContacts', 'contactPoints', 'contactsByLabel', 'findContacts',
           'scanContacts', 'GENERATE_OPTIONS', 'compareMany', 'generate', 'generateWith', 'score',
           'TEMPLATE_EXTENSIONS', 'ClumpSurface', 'MassProperties', 'MssResult', 'readSpheres', 'MESH_EXT', 'Mesh',
           'checkedPlane', 'flatArray', 'massProperties', 'readGrain', 'VOLUME_EXT', 'Region', 'binaryValue',
           'pieces', 'readVolume', 'regions', 'SPECK_VOXELS', 'segmentBinary', 'segmentScan', 'separated',
           'slabVoxels', 'valueRange']
