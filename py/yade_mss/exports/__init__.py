"""Exports: a clump as another DEM code's template, with the grain's exact mass properties (``mss export``,
:meth:`MssResult.export`, a batch's ``--format``). One module a format, each registering a :class:`Format` in
:data:`FORMATS` (``_registry.py`` says how to add one); ``_writers.py`` writes them.

Every number is written as Python's repr of the double (17 significant digits at most, read back exactly).
"""

from ._common import MARK, quaternion, templateFrame
from ._registry import FORMATS, Format, register
from ._writers import checkedOptions, exportTemplate, writeTemplates
# the formats, each registered on import, in the order the option table lists them
from ._liggghts import MAX_TEMPLATES, liggghtsTemplate, seed
from ._kratos import kratosCluster
from ._mercurydpm import mercuryFiles
from ._pfc import pfcTemplate
from ._yadetext import HEADER, parseClumps, yadeClumps

__all__ = ['MARK', 'quaternion', 'templateFrame', 'FORMATS', 'Format', 'register', 'checkedOptions',
           'exportTemplate', 'writeTemplates', 'MAX_TEMPLATES', 'liggghtsTemplate', 'seed', 'kratosCluster',
           'mercuryFiles', 'pfcTemplate', 'HEADER', 'parseClumps', 'yadeClumps']
