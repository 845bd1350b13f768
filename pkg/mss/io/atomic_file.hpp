// Files written whole or not at all (internal: the sphere writers and the command line).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace mss::detail {

/// Writes @p text to @p path through a new temporary file beside it (created exclusively, O_CREAT|O_EXCL,
/// under an unpredictable name: mkstemp) and a rename, so a reader sees the old file or the new one, never a
/// part. Only a regular file or a new path is replaced: a symbolic link, device, FIFO or directory there is
/// refused, as is following a link planted at a predictable temporary name (there is none). Throws
/// std::invalid_argument("WHERE: PATH: ...") naming the problem.
void writeFileAtomically(const std::string& where, const std::string& path, const std::string& text);

/// Whether @p a and @p b name the same existing file (device and inode: through links and other names).
bool sameFile(const std::string& a, const std::string& b);

/// Before any work: throws std::invalid_argument("WHERE: WHAT PATH is the input ...") where an output (a
/// (what, path) pair: {"-o", "out.csv"}) is one of @p inputs or another output, so that no command writes
/// over what it reads. Paths that do not exist are no input.
void refuseOverInputs(const std::string& where,
                      const std::vector<std::pair<std::string, std::string>>& outputs,
                      const std::vector<std::string>& inputs);

} // namespace mss::detail
