"""What every template format shares: numbers written exactly, safe comment text, the template's frame
(the grain's centre of mass and axes), names, and folders written whole."""

import os
import re
import shutil
import tempfile

import numpy as np

from ..base import umask


def number(x):
    return repr(float(x))


def safe(text):
    """A name for a comment line: anything but printable ASCII becomes '?', so that a file named with a newline
    cannot end the comment and put a command into the script."""
    return re.sub(r'[^ -~]', '?', str(text))


def whereGenerated(mark, centroid, R):
    """The header's two lines that put a template back where its grain was generated (readSpheres reads them):
    "c = x y z" and "R = rows", after the comment mark *mark*."""
    return ['%sc = %s' % (mark, ' '.join(number(x) for x in centroid)),
            '%sR = %s (rows)' % (mark, ' ; '.join(' '.join(number(x) for x in row) for row in R))]


def templateFrame(result, frame='principal'):
    """The spheres and the grain's inertia in the template's frame, whose origin is the grain's centre of mass.

    :param frame: 'principal' (the axes are the grain's principal axes of inertia, ascending moments) or
        'generated' (the axes the grain was generated in)
    :return: (centres (n, 3), radii (n,), inertia per unit density (3, 3), rotation R, centroid c): a body point
        p is at c + R p in the generated frame
    """
    m = result.targetMass
    if m is None:
        raise ValueError('export: the result has no grain mass properties (a bare sphere file): export the '
                         'grain (mesh or volume) or its saved result (.npz)')
    if frame == 'principal':
        w, R = m.principal()
        inertia = np.diag(w)  # diagonal by construction: R^T I R leaves rounding off the diagonal
    elif frame == 'generated':
        R, inertia = np.eye(3), m.inertia
    else:
        raise ValueError("export: frame must be 'principal' or 'generated', got %r" % (frame,))
    centres = (np.asarray(result.centers, dtype=float) - m.centroid) @ R
    return centres, np.asarray(result.radii, dtype=float), inertia, R, m.centroid.copy()


def templateName(result):
    """A one-word name for the template (Kratos reads the word after Name; MercuryDPM names the clump by its
    folder): the source's stem, with anything but letters, digits, '_', '-' and '.' made '_'."""
    stem = os.path.splitext(os.path.basename(str(result.source or '')))[0]
    return re.sub(r'[^A-Za-z0-9_.-]', '_', stem).strip('.') or 'mss_clump'


def principalOnly(fmt, frame):
    if frame != 'principal':
        raise ValueError("export: %s takes the template in its principal axes (it reads three principal moments "
                         "and puts the principal axes along x, y, z): use frame 'principal'" % fmt)


MARK = 'mss_export.txt'


def writeFolder(path, files):
    """Writes *files* ({relative path: text}) as the folder *path*, whole or not at all: built beside it under
    an unpredictable name, then renamed onto it. An existing folder is replaced only if this command wrote it
    (it holds mss_export.txt); a file, link or foreign folder there is refused."""
    path = os.path.abspath(os.fspath(path))
    if os.path.islink(path) or (os.path.lexists(path) and not os.path.isdir(path)):
        raise RuntimeError('export: %s: exists and is not a folder: not replaced' % path)
    if os.path.isdir(path) and not os.path.isfile(os.path.join(path, MARK)):
        raise RuntimeError('export: %s: a folder mss export did not write (no %s): not replaced' % (path, MARK))
    parent = os.path.dirname(path)
    try:
        tmp = tempfile.mkdtemp(prefix='.%s.' % os.path.basename(path)[:64], dir=parent)
    except OSError as e:
        raise RuntimeError('export: %s: cannot write (%s)' % (path, e))
    old = None
    try:
        for rel, text in files.items():
            os.makedirs(os.path.dirname(os.path.join(tmp, rel)), exist_ok=True)
            with open(os.path.join(tmp, rel), 'x') as f:
                f.write(text)
        os.chmod(tmp, 0o777 & ~umask())
        if os.path.isdir(path):
            old = tempfile.mkdtemp(prefix='.%s.old.' % os.path.basename(path)[:64], dir=parent)
            os.rename(path, os.path.join(old, 'x'))
        os.rename(tmp, path)
    except BaseException as e:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and os.path.isdir(os.path.join(old, 'x')) and not os.path.exists(path):
            os.rename(os.path.join(old, 'x'), path)  # put the earlier one back
        if isinstance(e, OSError):
            raise RuntimeError('export: %s: cannot write (%s)' % (path, e))
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


def quaternion(R):
    """The unit quaternion (w, x, y, z), w >= 0, of the rotation matrix *R* (the largest of the four candidates
    is computed first, so that none divides by a small number)."""
    R = np.asarray(R, dtype=float)
    t = np.trace(R)
    cands = [t, R[0, 0], R[1, 1], R[2, 2]]
    i = int(np.argmax(cands))
    if i == 0:
        w = np.sqrt(1 + t) / 2
        q = [w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)]
    else:
        a, b, c = (i - 1, i % 3, (i + 1) % 3)
        v = np.sqrt(1 + R[a, a] - R[b, b] - R[c, c]) / 2
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (R[c, b] - R[b, c]) / (4 * v)
        q[1 + a], q[1 + b], q[1 + c] = v, (R[b, a] + R[a, b]) / (4 * v), (R[c, a] + R[a, c]) / (4 * v)
    q = np.array(q)
    return q if q[0] >= 0 else -q
