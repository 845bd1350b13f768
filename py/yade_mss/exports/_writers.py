"""Writing templates: one (:func:`exportTemplate`, ``mss export``) or a batch's (:func:`writeTemplates`), each
format found in the registry."""

import csv
import os

from ..base import atomicWrite
from ..grains import optionTable
from ._common import MARK, number, quaternion, writeFolder
from ._registry import FORMATS


def writeTemplates(outdir, b, fmt, density):
    """A batch's grains as *fmt*'s templates, one per grain in the principal axes (OUTDIR/templates/, written
    whole: a rerun leaves none of an earlier run's), and OUTDIR/placements.csv: where each goes (its centre of
    mass and the rotation from template to world as a quaternion w x y z; a template point p is at c + R p) and
    its mass. LIGGGHTS: the templates are types 1, 2, ... in the batch's order, and templates/templates.in
    includes them all."""
    files, rows = {MARK: 'templates written by mss batch --format %s (density %s): one per grain, placements '
                   'in ../placements.csv\n' % (fmt, number(density))}, []
    f = FORMATS[fmt]
    for i, (key, r) in enumerate(b.results.items(), 1):
        name = key + f.extension
        out = f.write(r, {'density': density, 'frame': 'principal', 'templateType': i, 'atomType': 1})
        if f.folder:
            files.update({os.path.join(key, rel): text for rel, text in out.items()})
        else:
            files[name] = out
        m = r.targetMass
        _, R = m.principal()
        rows.append([key, b.rows[key]['label'], os.path.join('templates', name), i] + [number(x) for x in m.centroid]
                    + [number(x) for x in quaternion(R)] + [number(density * m.volume)])
    if f.index is not None:
        files.update(f.index([key + f.extension for key in b.results]))
    writeFolder(os.path.join(outdir, 'templates'), files)

    def table(p):
        with open(p, 'w', newline='') as out:
            w = csv.writer(out)
            w.writerow(['grain', 'label', 'template', 'type', 'x', 'y', 'z', 'qw', 'qx', 'qy', 'qz', 'mass'])
            w.writerows(rows)
    atomicWrite(os.path.join(outdir, 'placements.csv'), table, 'batch')


def checkedOptions(given):
    """The export options in *given* (None: the table's default), checked against the table."""
    return {k: optionTable.check('export', 'export', k, v if v is not None else optionTable.default(k, 'export'))
            for k, v in given.items()}


def exportTemplate(result, path, format=None, density=None, frame=None, templateType=None, atomType=None):
    """Writes *result* as *format*'s template to *path* (atomically), with the grain's exact mass properties
    (the options are ``mss export``'s; None: the table's default).

    :param result: an :class:`MssResult` (generated from a grain, or loaded from its .npz)
    :param format: 'liggghts' (an input-script file to include), 'kratos' (a .clu cluster file), 'mercurydpm'
        (a folder, the clump's name, as MClump writes it), 'pfc' (a PFC3D data file with ``clump template
        create``) or 'yade' (a yade-mss clumps file, for :func:`yade_mss.readClumps`)
    :param float density: mass per world unit cubed; the mass is it times the grain's exact volume (Kratos and
        PFC: not written, the material's or replication's density applies)
    :param frame: 'principal' or 'generated' (see :func:`yade_mss.exports.templateFrame`; kratos and
        mercurydpm: principal; pfc and yade: the generated frame keeps the pebbles where they were generated)
    :param int templateType: the template's number (LIGGGHTS: consecutive from 1)
    :param int atomType: the spheres' atom (material) type (LIGGGHTS)
    """
    o = checkedOptions(dict(format=format, density=density, frame=frame, templateType=templateType, atomType=atomType))
    f = FORMATS[o['format']]
    text = f.write(result, o)
    if f.folder:
        writeFolder(path, text)
        return

    def write(p):
        with open(p, 'w') as out:
            out.write(text)
    atomicWrite(path, write, 'export')
