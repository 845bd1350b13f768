// Internal to the readers: what a path must be before a reader opens it.
#pragma once

#include <stdexcept>
#include <string>

#include <sys/stat.h>

namespace mss::detail {

/// Refuses a path that is not a regular file, by name: a FIFO would block the reader at open, a character
/// device
/// (/dev/zero) never end, a directory or socket has no bytes to read. A missing path passes (the reader says
/// it cannot open it). Throws std::invalid_argument("WHERE: PATH: not a regular file (a FIFO)").
inline void requireRegularFile(const std::string& where, const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || S_ISREG(st.st_mode)) return;
    const char* kind = S_ISDIR(st.st_mode)    ? "a directory"
                       : S_ISFIFO(st.st_mode) ? "a FIFO"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "not a file";
    throw std::invalid_argument(where + ": " + path + ": not a regular file (" + kind + ")");
}

} // namespace mss::detail
