// Internal to the mesh readers (mesh_readers.cpp, stl_reader.cpp): a file's bytes and the error every reader
// throws.
#pragma once

#include "mss/mesh.hpp"

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#if defined(__linux__)
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#endif

namespace mss::detail {

/// The readers' error: names the file and the problem.
[[noreturn]] inline void fail(const std::string& path, const std::string& what) {
    throw std::invalid_argument("readMesh: " + path + ": " + what);
}

/// A whole file in memory, read-only: mapped (the femur's 2.7 MB ASCII STL in 0.16 ms; read into fresh memory
/// it took 1.2 ms, most of it first touches of the new pages), or where mapping fails read in one piece (a
/// byte-by-byte stream iterator took a third of reading an ASCII STL). Empty for a file that is not a
/// regular file or cannot be read.
class FileBytes {
public:
    explicit FileBytes(const std::string& path) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) return; // (a directory's size is no size)
#if defined(__linux__)
        const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) return;
        struct stat st {};
        if (::fstat(fd, &st) == 0 && st.st_size > 0) {
            void* m = ::mmap(nullptr, std::size_t(st.st_size), PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
            if (m != MAP_FAILED) {
                map_ = m;
                data_ = static_cast<const char*>(m);
                size_ = std::size_t(st.st_size);
            }
        }
        ::close(fd);
        if (map_) return;
#endif
        const std::uintmax_t size = std::filesystem::file_size(path, ec);
        std::ifstream in(path, std::ios::binary);
        if (ec || !in || size == 0) return;
        copy_.resize(static_cast<std::size_t>(size));
        in.read(copy_.data(), static_cast<std::streamsize>(size));
        copy_.resize(static_cast<std::size_t>(in.gcount()));
        data_ = copy_.data();
        size_ = copy_.size();
    }
    ~FileBytes() {
#if defined(__linux__)
        if (map_) ::munmap(map_, size_);
#endif
    }
    FileBytes(const FileBytes&) = delete;
    FileBytes& operator=(const FileBytes&) = delete;

    const char* data() const {
        return data_;
    }
    std::size_t size() const {
        return size_;
    }
    char operator[](std::size_t i) const {
        return data_[i];
    }

private:
    const char* data_ = nullptr;
    std::size_t size_ = 0;
    void* map_ = nullptr;
    std::vector<char> copy_;
};

/// Reads an STL file, ASCII or binary (stl_reader.cpp).
TriangleMesh readStl(const std::string& path);

} // namespace mss::detail
