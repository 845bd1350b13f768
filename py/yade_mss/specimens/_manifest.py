"""A finished batch's manifest (OUTDIR/batch.json): what it was made from and what it wrote, so that a rerun of
the same command with nothing changed costs a look at the files, not a run (make-like).

The inputs are known by their identity on disk (device, inode, size, modification and change times in
nanoseconds; an array by a digest of its bytes), the options by their values, the outputs by their identity
too: a file rewritten, replaced or removed since (a grain's result swapped in grains/, an input edited or
touched) sends the rerun down the ordinary path, which reuses each grain only for the same input and options.
The manifest holds the digest of its own content, so an edited one (its state rows, which a rerun would give
back) is stale too, as is one too large, too deeply nested or unreadable.
"""

import hashlib
import json
import os
import stat
from json.encoder import encode_basestring_ascii as _quoted

import numpy as np

VERSION = 4  # 3: the outputs as a count and a digest; 4: each output's line not JSON (a tenth of the time)
NAME = 'batch.json'
MAX_BYTES = 1 << 30  # a manifest is mostly rows: 10^5 grains take tens of MB


def _identity(path):
    st = os.stat(path)
    return [st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns]


def inputIdentity(files=None, array=None):
    """What a batch is made from: each file's path and identity on disk, or an array's shape, type and digest."""
    if array is not None:
        a = np.ascontiguousarray(array)
        return {'array': [list(a.shape), a.dtype.str, hashlib.sha256(memoryview(a).cast('B')).hexdigest()]}
    return {'files': [[os.path.abspath(f)] + _identity(f) for f in files]}


def outputs(outdir):
    """What the batch left in *outdir* (the manifest aside): the count of its regular files and a digest of
    their relative paths and identities, folder by folder in name order (a listing of 10^5 grains' files
    held whole cost a hundred MB)."""
    h, n = hashlib.sha256(), 0
    stack = ['']
    while stack:
        rel = stack.pop()
        top = os.path.join(outdir, rel)
        with os.scandir(top) as it:
            names = sorted(e.name for e in it)  # names only: 10^5 grains' entries held were 250 MB
        below, prefix = [], os.path.join(rel, '')
        fd = os.open(top, os.O_RDONLY | getattr(os, 'O_DIRECTORY', 0))
        try:
            for name in names:
                if rel == '' and name == NAME:
                    continue
                st = os.stat(name, dir_fd=fd, follow_symlinks=False)  # beside the folder: no path to resolve
                if stat.S_ISDIR(st.st_mode):  # a link to a folder is not walked
                    below.append(prefix + name)
                elif stat.S_ISREG(st.st_mode) and not name.startswith('.'):  # a lock, a temporary file: not outputs
                    n += 1
                    # the path quoted as JSON quotes it (no name can end its line early), then the identity
                    h.update(b'%s %d %d %d %d %d\n' % (_quoted(prefix + name).encode(), st.st_dev, st.st_ino,
                                                        st.st_size, st.st_mtime_ns, st.st_ctime_ns))
        finally:
            os.close(fd)
        stack.extend(reversed(below))
    return {'files': n, 'digest': h.hexdigest()}


def forget(outdir):
    """Removes the manifest: a run that changes the folder makes it stale."""
    try:
        os.remove(os.path.join(outdir, NAME))
    except FileNotFoundError:
        pass


def write(outdir, key, state, atomic):
    """Writes the manifest of a finished batch: its *key* (inputs and options), the files in *outdir* now and
    *state* (what the summary and the Python API give back), then the digest of that content (:func:`read`
    checks it). The text is made once, digested and written piece by piece: the manifest of 10^5 grains is
    tens of MB of text, and making it twice cost a third of this."""
    body = {'version': VERSION, 'key': key, 'outputs': outputs(outdir), 'state': state}

    def put(p):
        h = hashlib.sha256()
        with open(p, 'w') as f:
            last = None
            for chunk in _chunks(body):
                if last is not None:
                    h.update(last.encode())
                    f.write(last)
                last = chunk
            h.update(last.encode())  # the content's closing brace: the sum goes before it, digested without it
            f.write(last[:-1] + ', "sum": "%s"}' % h.hexdigest())
    atomic(os.path.join(outdir, NAME), put)


def contentDigest(data):
    """The digest of JSON-able *data* as read back from JSON (the same text before writing and after reading):
    the manifest's own, a grain record's row. Their keys are text, so their JSON with sorted keys is the read
    data's; the text is digested piece by piece (:func:`_chunks`), never whole (a manifest of 10^5 rows)."""
    h = hashlib.sha256()
    for chunk in _chunks(data):
        h.update(chunk.encode())
    return h.hexdigest()


WHOLE = 256  # a dict or list of up to this many entries, below the top levels, is encoded in one piece


def _chunks(data, depth=0):
    """``json.dumps(data, sort_keys=True, default=str)`` in pieces (its keys are text): large dicts and lists,
    and the top levels that hold them, entry by entry; the rest whole (the C encoder: a grain's row is one
    piece)."""
    if isinstance(data, dict) and (len(data) > WHOLE or (depth < 2 and any(
            isinstance(v, (dict, list, tuple)) and len(v) > WHOLE for v in data.values()))):
        yield '{'
        for i, k in enumerate(sorted(data)):
            yield (', ' if i else '') + json.dumps(k) + ': '
            yield from _chunks(data[k], depth + 1)
        yield '}'
    elif isinstance(data, (list, tuple)) and len(data) > WHOLE:
        yield '['
        for i, v in enumerate(data):
            if i:
                yield ', '
            yield from _chunks(v, depth + 1)
        yield ']'
    else:
        yield json.dumps(data, sort_keys=True, default=str)


def read(outdir):
    """The manifest of *outdir* as its batch wrote it: None where there is none, or it is not a regular file, over
    MAX_BYTES, nested too deep, unreadable, of another version, or edited since (its digest)."""
    path = os.path.join(outdir, NAME)
    try:
        st = os.lstat(path)
        if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_BYTES:
            return None
        with open(path) as f:
            meta = json.load(f)
        if not isinstance(meta, dict) or meta.get('version') != VERSION:
            return None
        if meta.get('sum') != contentDigest({k: meta.get(k) for k in ('version', 'key', 'outputs', 'state')}):
            return None  # edited since it was written
        return meta
    except (OSError, ValueError, TypeError, RecursionError):  # a nesting too deep for the parser: stale
        return None


def finished(outdir, key):
    """The *state* of a finished batch in *outdir* made with the same *key*, whose every output is as it left
    it; None otherwise (no manifest, another key, a file changed, added or gone, a manifest unreadable)."""
    meta = read(outdir)
    if meta is None or meta.get('key') != key:
        return None
    try:
        if outputs(outdir) != meta.get('outputs'):
            return None
    except OSError:
        return None
    return meta.get('state')
