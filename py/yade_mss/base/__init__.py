"""The bottom layer of the Python package: argument checks, keyword splitting, files written whole, folder
locks, work in a forked child alongside, the work limit, rotations and stopping once on a signal. It imports nothing of the package but the C++
module (``yade_mss._mss``).

Every layer above may use these names; they are not part of the user's API (:mod:`yade_mss` is).
"""

from ._alongside import alongside, canFork
from ._args import INT64_MAX, INT_MAX, choice, flag, integer, number, numberList, optional, vector, vector3
from ._files import (atomicWrite, cppPath, folderLock, memoryBytes, readNpy, readTiff, refuseLinkedFolders,
                     refuseOverInputs, releaseFreed, requireRegularFile, umask)
from ._keywords import split
from ._rotations import quaternionMatrix, randomRotation
from ._signals import exitStatus, restore as restoreSignals, stopOnce
from ._work import bar as progressBar, check as checkWork, checkSweep, slowPhase

__all__ = ['alongside', 'canFork', 'INT64_MAX', 'INT_MAX', 'choice', 'flag', 'integer', 'number', 'numberList', 'optional', 'vector',
           'vector3', 'atomicWrite', 'cppPath', 'folderLock',
           'memoryBytes', 'readNpy', 'readTiff', 'refuseLinkedFolders', 'refuseOverInputs', 'releaseFreed',
           'requireRegularFile',
           'umask', 'split', 'quaternionMatrix', 'randomRotation', 'progressBar', 'checkWork', 'checkSweep',
           'exitStatus', 'restoreSignals', 'stopOnce', 'slowPhase']
