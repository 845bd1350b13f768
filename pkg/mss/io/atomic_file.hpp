// Files written whole or not at all (internal: the sphere writers and the command line).
#pragma once

#include <string>

namespace mss::detail {

/// Writes @p text to @p path through a new temporary file beside it (created exclusively, O_CREAT|O_EXCL,
/// under an unpredictable name: mkstemp) and a rename, so a reader sees the old file or the new one, never a
/// part. Only a regular file or a new path is replaced: a symbolic link, device, FIFO or directory there is
/// refused, as is following a link planted at a predictable temporary name (there is none). Throws
/// std::invalid_argument("WHERE: PATH: ...") naming the problem.
void writeFileAtomically(const std::string& where, const std::string& path, const std::string& text);

} // namespace mss::detail
