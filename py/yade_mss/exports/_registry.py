"""The registry of template formats: one module a format registers itself here (as trimesh's ``exchange/``).

To add a format: write ``_name.py`` beside the others with a function from an :class:`MssResult` to the file's
text, register a :class:`Format` at its end, import it in ``__init__.py``, and add its name to the option
table's ``--format`` choices (pkg/mss/generation/option_table.cpp), which the command line and the keyword
checks read; tests/python/exports/test_registry.py fails until both agree.
"""


class Format(object):
    """One DEM code's template.

    :param str name: the ``--format`` choice
    :param str extension: what a batch appends to a grain's name ('' for a folder format)
    :param write: ``write(result, options)``: the file's text, or {relative path: text} for a folder format;
        *options* holds density, frame, templateType and atomType, checked against the option table
    :param bool folder: the template is a folder (written whole, :func:`writeFolder`)
    :param index: for a batch, ``index(names)``: {file: text} of files that list the batch's templates, or None
    """

    def __init__(self, name, extension, write, folder=False, index=None):
        self.name, self.extension, self.write, self.folder, self.index = name, extension, write, folder, index


FORMATS = {}  # name: Format, in the order registered


def register(fmt):
    """Adds *fmt* to :data:`FORMATS`; a name registered twice is a mistake in the package."""
    if fmt.name in FORMATS:
        raise ValueError('export: the format %r is registered twice' % fmt.name)
    FORMATS[fmt.name] = fmt
    return fmt
