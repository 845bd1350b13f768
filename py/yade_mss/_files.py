"""Files written whole or not at all: an exclusive temporary file beside the target, then a rename."""

import os
import stat
import tempfile


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomicWrite(path, write, where):
    """Calls ``write(tmp)`` on a new temporary path beside *path* (created exclusively, O_CREAT|O_EXCL, under an
    unpredictable name, with the same extension), then renames it onto *path*; nothing is left behind if
    anything fails. Only a regular file or a new path is replaced: a symbolic link, device, FIFO or directory
    at *path* is refused. An OSError becomes RuntimeError('WHERE: PATH: cannot write ...')."""
    path = os.fspath(path)
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise RuntimeError('%s: %s: cannot write (%s)' % (where, path, e))
    if st is not None and not stat.S_ISREG(st.st_mode):
        raise RuntimeError('%s: %s: exists and is not a regular file (a link, device, FIFO or directory): not '
                           'replaced' % (where, path))
    folder = os.path.dirname(path) or '.'
    try:
        fd, tmp = tempfile.mkstemp(prefix='.%s.' % os.path.basename(path)[:64], suffix=os.path.splitext(path)[1],
                                   dir=folder)
        os.fchmod(fd, 0o666 & ~_umask())  # as an ordinary new file, not mkstemp's 0600
        os.close(fd)
    except OSError as e:
        raise RuntimeError('%s: %s: cannot write (%s)' % (where, path, e))
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as e:
        if os.path.lexists(tmp):
            os.remove(tmp)
        if isinstance(e, OSError):
            raise RuntimeError('%s: %s: cannot write (%s)' % (where, path, e))
        raise


def requireRegularFile(where, path):
    """Refuses a path that is not a regular file, by name (a FIFO would block the reader; a device never end). A
    missing path passes: the reader says it cannot open it."""
    try:
        st = os.stat(path)
    except OSError:
        return
    if not stat.S_ISREG(st.st_mode):
        kind = ('a directory' if stat.S_ISDIR(st.st_mode) else 'a FIFO' if stat.S_ISFIFO(st.st_mode) else
                'a character device' if stat.S_ISCHR(st.st_mode) else 'a block device' if stat.S_ISBLK(st.st_mode)
                else 'a socket' if stat.S_ISSOCK(st.st_mode) else 'not a file')
        raise ValueError('%s: %s: not a regular file (%s)' % (where, os.fspath(path), kind))


class cppPath(object):
    """A path the C++ readers can take (Boost.Python passes UTF-8 text): *path* itself, or, for a name whose
    bytes are not UTF-8, a link of a UTF-8 name (the same extension) in a private temporary folder, while the
    block runs; an error that names the link names the file instead (its bytes escaped).
    ``with cppPath(path) as p: _mss.readMesh(p)``"""

    def __init__(self, path):
        self.path, self.folder = os.fspath(path), None

    def __enter__(self):
        try:
            self.path.encode('utf-8')
            return self.path
        except UnicodeEncodeError:
            pass
        self.folder = tempfile.mkdtemp(prefix='mss-path-')
        self.link = os.path.join(self.folder, 'file' + os.path.splitext(self.path)[1].encode(
            'ascii', 'replace').decode('ascii'))
        os.symlink(os.path.abspath(os.fsencode(self.path)), os.fsencode(self.link))
        return self.link

    def __exit__(self, kind, error, trace):
        if self.folder is not None:
            os.remove(self.link)
            os.rmdir(self.folder)
            if isinstance(error, ValueError) and self.link in str(error):
                shown = self.path.encode('utf-8', 'backslashreplace').decode('utf-8')
                raise ValueError(str(error).replace(self.link, shown)) from None
        return False
