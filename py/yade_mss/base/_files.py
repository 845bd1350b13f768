"""Files written whole or not at all: an exclusive temporary file beside the target, then a rename."""

import os
import secrets
import stat
import tempfile


def umask():
    """The process's file-creation mask (read without changing it)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomicWrite(path, write, where, data=None):
    """Calls ``write(tmp)`` on a new temporary path beside *path* (created exclusively, O_CREAT|O_EXCL, under an
    unpredictable name, with the same extension), then renames it onto *path*; nothing is left behind if
    anything fails. Only a regular file or a new path is replaced: a symbolic link, device, FIFO or directory
    at *path* is refused. An OSError becomes RuntimeError('WHERE: PATH: cannot write ...'). *data*: bytes
    written instead of calling *write* (None then), through the descriptor the file was made with."""
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
    folder, name = os.path.split(path)
    fd = tmp = None
    for _ in range(100):  # as mkstemp: another name where one exists (a batch writes 10^5 files: no fchmod)
        tmp = os.path.join(folder, '.%s.%s%s' % (name[:64], secrets.token_hex(6), os.path.splitext(path)[1]))
        try:  # an ordinary new file's permissions (0666 less the umask), never through a link planted there
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, 'O_NOFOLLOW', 0), 0o666)
            break
        except FileExistsError:
            continue
        except OSError as e:
            raise RuntimeError('%s: %s: cannot write (%s)' % (where, path, e))
    if fd is None:
        raise RuntimeError('%s: %s: cannot write (no free temporary name beside it)' % (where, path))
    try:  # from here on a Ctrl-C or an error leaves no temporary file behind
        if data is not None:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view):]
        os.close(fd)
        fd = None
        if data is None:
            write(tmp)
        os.replace(tmp, path)
    except BaseException as e:
        if fd is not None:
            os.close(fd)
        if os.path.lexists(tmp):
            os.remove(tmp)
        if isinstance(e, OSError):
            raise RuntimeError('%s: %s: cannot write (%s)' % (where, path, e))
        raise


def refuseOverInputs(where, outputs, inputs):
    """Before any work: refuses an output that is one of the inputs (the same file by device and inode, through
    links and other names), naming both, so that no command writes over what it reads. *outputs*: (what, path)
    pairs ('-o', 'out.csv'); *inputs*: paths (those that do not exist yet are no input)."""
    ids = {}
    for path in inputs:
        try:
            st = os.stat(path)
        except (OSError, TypeError, ValueError):
            continue
        ids.setdefault((st.st_dev, st.st_ino), os.fspath(path))
    seen = {}
    for what, path in outputs:
        if path is None:
            continue
        try:
            st = os.stat(path)
        except (OSError, TypeError, ValueError):
            continue
        key = (st.st_dev, st.st_ino)
        if key in ids:
            raise ValueError('%s: %s %s is the input %s (the same file%s): it would be written over; name another '
                             'output' % (where, what, os.fspath(path), ids[key],
                                         '' if os.fspath(path) == ids[key] else ', through a link or another name'))
        if key in seen:
            raise ValueError('%s: %s and %s name the same file %s: one would write over the other'
                             % (where, seen[key], what, os.fspath(path)))
        seen[key] = what


def refuseLinkedFolders(where, folders):
    """Refuses an output folder, or a folder the command writes into inside it, that is a symbolic link: files
    would land wherever the link points (a link planted in a shared output folder)."""
    for path in folders:
        path = os.path.normpath(os.fspath(path))  # 'lnk/' and 'lnk/.' name the link itself, not its target
        if os.path.islink(path):
            raise ValueError('%s: %s is a symbolic link: the outputs would be written where it points (%s); give '
                             'a real folder' % (where, os.fspath(path), os.path.realpath(path)))


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


def memoryBytes():
    """The machine's physical memory in bytes (16 GiB where it cannot be read): the guards allow half."""
    try:
        return os.sysconf('SC_PHYS_PAGES') * os.sysconf('SC_PAGE_SIZE')
    except (ValueError, OSError):
        return 1 << 34


_LIBC = []


def releaseFreed():
    """Hands the memory freed since back to the system (glibc's malloc_trim), after a phase that allocated and
    freed much (a scan's contacts: the C++ side's tables, the slabs): glibc keeps freed blocks of the heap for
    reuse, and a batch of 10^4 grains kept 50 MB so. Nothing where the C library has no such call."""
    if not _LIBC:
        import ctypes
        import ctypes.util
        try:
            _LIBC.append(ctypes.CDLL(ctypes.util.find_library('c') or 'libc.so.6').malloc_trim)
        except (OSError, AttributeError):
            _LIBC.append(None)
    if _LIBC[0] is not None:
        _LIBC[0](0)


def readNpy(where, path, mmap=False):
    """A .npy array, its header checked before numpy reads the data: the magic, a header numpy parses, no Python
    objects, and data the file really holds (a header may declare any shape). Every failure, whatever the parser
    raised, is ValueError('WHERE: PATH: ...')."""
    import numpy as np
    path = os.fspath(path)
    requireRegularFile(where, path)
    try:
        with open(path, 'rb') as f:
            if f.read(6) != b'\x93NUMPY':
                raise ValueError('not a .npy file (it does not start with \\x93NUMPY)')
            f.seek(0)
            version = np.lib.format.read_magic(f)
            if version == (1, 0):
                shape, _, dtype = np.lib.format.read_array_header_1_0(f)
            elif version == (2, 0):
                shape, _, dtype = np.lib.format.read_array_header_2_0(f)
            else:
                raise ValueError('.npy format version %d.%d (1.0 and 2.0 are read)' % version)
            if dtype.hasobject:
                raise ValueError('it holds Python objects (dtype %s), which are never unpickled' % dtype)
            need, have = int(np.prod(shape, dtype=object)) * dtype.itemsize, os.fstat(f.fileno()).st_size - f.tell()
            if need > have:
                raise ValueError('its header declares shape %s of %s (%d bytes), the file holds %d'
                                 % (tuple(shape), dtype, need, have))
        return np.load(path, mmap_mode='r' if mmap else None, allow_pickle=False)
    except Exception as e:  # a parser of hostile bytes: SyntaxError, TokenError, OverflowError, ... all say the same
        if isinstance(e, ValueError) and str(e).startswith(where):
            raise
        raise ValueError('%s: %s: cannot read the .npy file (%s)' % (where, path, e)) from None


def readTiff(where, path):
    """A TIFF stack as one array (memory-mapped where the file stores it whole and uncompressed), its declared size
    checked against the memory before anything is expanded. Every
    failure of the reader (tifffile raises its own TiffFileError, struct.error, KeyError, ...) is
    ValueError('WHERE: PATH: ...')."""
    import numpy as np
    import tifffile
    path = os.fspath(path)
    requireRegularFile(where, path)
    try:
        with tifffile.TiffFile(path) as t:
            if not t.series:
                raise ValueError('it holds no image')
            s = t.series[0]
            need, limit = int(np.prod(s.shape, dtype=object)) * np.dtype(s.dtype).itemsize, memoryBytes() // 2
            if need > limit:
                raise ValueError('it declares shape %s of %s (%d bytes), more than half the memory (%d bytes)'
                                 % (tuple(s.shape), s.dtype, need, limit))
            if s.dataoffset is not None:  # stored whole and uncompressed: mapped, so a CT stays on disk
                dtype = np.dtype(s.dtype).newbyteorder(t.byteorder)
                if s.dataoffset + need > os.path.getsize(path):
                    raise ValueError('its data (%d bytes at %d) run past the end of the file' % (need, s.dataoffset))
                return np.memmap(path, dtype=dtype, mode='r', offset=s.dataoffset, shape=tuple(s.shape))
            return t.asarray()
    except Exception as e:  # as readNpy's
        raise ValueError('%s: %s: cannot read the TIFF (%s)' % (where, path, e)) from None


class folderLock(object):
    """An exclusive lock on an output folder for one job at a time (``with folderLock('batch', OUT): ...``): an
    ``fcntl`` lock on OUT/.mss.lock, taken at once or refused with whose it is (process, host, since when). The
    kernel drops the lock of a process that is gone, so a stale lock file is simply taken over. The folder is
    made if it is missing, and removed again if the job left nothing else in it (a job refused before any work
    leaves no folder behind); a lock file that is a link or not a regular file is refused."""

    NAME = '.mss.lock'

    def __init__(self, where, folder):
        self.where, self.folder, self.fd, self.made = where, os.fspath(folder), None, False

    def __enter__(self):
        import fcntl
        import json
        import socket
        import time
        path = os.path.join(self.folder, self.NAME)
        try:
            self.made = not os.path.lexists(self.folder)
            os.makedirs(self.folder, exist_ok=True)
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK,
                         0o666 & ~umask())  # non-blocking: a FIFO planted there does not hang the open
        except OSError as e:
            raise RuntimeError('%s: %s: cannot take the folder\'s lock %s (%s)' % (self.where, self.folder, path, e))
        try:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise RuntimeError('%s: %s: not a regular file: not used as a lock' % (self.where, path))
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                try:
                    holder = json.loads(os.pread(fd, 4096, 0).decode('utf-8', 'replace'))
                    who = 'process %d on %s, since %s' % (int(holder['pid']), str(holder['host'])[:64],
                                                          str(holder['since'])[:32])
                except (ValueError, KeyError, TypeError):
                    who = 'another process'
                raise RuntimeError('%s: %s is in use by another job (%s): wait for it to end, or name another '
                                   'output folder' % (self.where, self.folder, who))
            os.ftruncate(fd, 0)
            os.pwrite(fd, json.dumps(dict(pid=os.getpid(), host=socket.gethostname(),
                                          since=time.strftime('%Y-%m-%dT%H:%M:%S'))).encode(), 0)
        except BaseException:
            os.close(fd)
            raise
        self.fd = fd
        return self

    def __exit__(self, *exc):
        if self.fd is None:
            return False
        try:
            if self.made and os.listdir(self.folder) == [self.NAME]:  # made here, and nothing came of it
                os.remove(os.path.join(self.folder, self.NAME))
                os.rmdir(self.folder)
        except OSError:
            pass
        finally:  # otherwise the file stays: removing it would race a job taking it
            os.close(self.fd)
            self.fd = None
        return False
