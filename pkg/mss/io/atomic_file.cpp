#include "mss/io/atomic_file.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace mss::detail {

namespace {
[[noreturn]] void fail(const std::string& where, const std::string& path, const std::string& what) {
    throw std::invalid_argument(where + ": " + path + ": " + what);
}
} // namespace

void writeFileAtomically(const std::string& where, const std::string& path, const std::string& text) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
        fail(where, path,
             "exists and is not a regular file (a link, device, FIFO or directory): not replaced");
    const std::size_t slash = path.rfind('/');
    const std::string dir = slash == std::string::npos ? "." : path.substr(0, slash == 0 ? 1 : slash);
    const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    std::string pattern = dir + "/." + base.substr(0, 64) + ".XXXXXX";
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back('\0');
    const int fd = ::mkstemp(name.data());
    if (fd < 0) fail(where, path, std::string("cannot write (") + std::strerror(errno) + ")");
    const std::string tmp(name.data());
    const mode_t mask = ::umask(0);
    ::umask(mask);
    bool ok = ::fchmod(fd, 0666 & ~mask) == 0; // as an ordinary new file, not mkstemp's 0600
    for (std::size_t done = 0; ok && done < text.size();) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        ok = n > 0;
        done += ok ? std::size_t(n) : 0;
    }
    const int saved = errno;
    ok = (::close(fd) == 0) && ok;
    if (!ok) {
        ::unlink(tmp.c_str());
        fail(where, path, std::string("write failed (") + std::strerror(saved) + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        fail(where, path, std::string("cannot write (") + std::strerror(e) + ")");
    }
}

bool sameFile(const std::string& a, const std::string& b) {
    struct stat x {
    }, y{};
    return ::stat(a.c_str(), &x) == 0 && ::stat(b.c_str(), &y) == 0 && x.st_dev == y.st_dev &&
           x.st_ino == y.st_ino;
}

void refuseOverInputs(const std::string& where,
                      const std::vector<std::pair<std::string, std::string>>& outputs,
                      const std::vector<std::string>& inputs) {
    for (std::size_t o = 0; o < outputs.size(); ++o) {
        const auto& [what, path] = outputs[o];
        for (const std::string& in : inputs)
            if (sameFile(path, in))
                throw std::invalid_argument(where + ": " + what + " " + path + " is the input " + in +
                                            (path == in ? " (the same file)"
                                                        : " (the same file, through a link or "
                                                          "another name)") +
                                            ": it would be written over; name another output");
        for (std::size_t p = 0; p < o; ++p)
            if (path == outputs[p].second || sameFile(path, outputs[p].second))
                throw std::invalid_argument(where + ": " + outputs[p].first + " and " + what +
                                            " name the same file " + path +
                                            ": one would write over the other");
    }
}

} // namespace mss::detail
