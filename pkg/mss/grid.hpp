// Regular voxel grids: the value type every stage of MSS reads and writes.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

namespace mss {

namespace detail {
/// Blocks of this many bytes or more are mapped on their own (platform/big_vector.cpp).
constexpr std::size_t kBigBlock = std::size_t(2) << 20;
/// A block of @p bytes (>= kBigBlock) aligned to 2 MiB, on transparent huge pages where the system has them.
void* allocateBig(std::size_t bytes);
/// Gives back a block of allocateBig().
void freeBig(void* p, std::size_t bytes) noexcept;
} // namespace detail

/// The allocator of grids' values: large blocks on huge pages (platform/big_vector.hpp says why), others from
/// std::allocator.
template <class T> struct BigAllocator {
    using value_type = T;
    BigAllocator() noexcept = default;
    template <class U> BigAllocator(const BigAllocator<U>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
        if (n * sizeof(T) >= detail::kBigBlock) return static_cast<T*>(detail::allocateBig(n * sizeof(T)));
        return std::allocator<T>().allocate(n);
    }
    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) >= detail::kBigBlock)
            detail::freeBig(p, n * sizeof(T));
        else
            std::allocator<T>().deallocate(p, n);
    }
    template <class U> bool operator==(const BigAllocator<U>&) const noexcept { return true; }
    template <class U> bool operator!=(const BigAllocator<U>&) const noexcept { return false; }
};

/// A std::vector whose large blocks lie on huge pages (see BigAllocator).
template <class T> using BigVector = std::vector<T, BigAllocator<T>>;

using Vec3 = Eigen::Vector3d;

/// Dimensions and placement of a regular grid of cubic voxels.
///
/// Memory order is x fastest, then y, then z: the linear index of voxel (i, j, k) is i + nx * (j + ny * k).
/// Voxel (i, j, k) has its centre at origin + h * (i, j, k) in world units; it covers the cube of edge h
/// around that centre. This is the voxel-centred lattice of MSS paper section 3.3 (eq. 23: r = h * (i, j,
/// k)), shifted by the world origin.
struct GridSpec {
    std::array<int, 3> dims{0, 0, 0}; ///< voxel counts nx, ny, nz
    double h = 1.0;                   ///< voxel edge length, world units
    Vec3 origin = Vec3::Zero();       ///< world position of the centre of voxel (0, 0, 0)

    std::size_t size() const {
        return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
               static_cast<std::size_t>(dims[2]);
    }
    std::size_t index(int i, int j, int k) const {
        return static_cast<std::size_t>(i) +
               static_cast<std::size_t>(dims[0]) *
                   (static_cast<std::size_t>(j) +
                    static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(k));
    }
    bool contains(int i, int j, int k) const {
        return i >= 0 && j >= 0 && k >= 0 && i < dims[0] && j < dims[1] && k < dims[2];
    }
    /// World position -> continuous voxel coordinates (voxel centres are integers). The one place index maths
    /// lives.
    Vec3 toVoxel(const Vec3& world) const { return (world - origin) / h; }
    /// Continuous voxel coordinates -> world position.
    Vec3 toWorld(const Vec3& voxel) const { return origin + h * voxel; }
    Vec3 voxelCenter(int i, int j, int k) const { return toWorld(Vec3(i, j, k)); }
    /// Index of the voxel whose cube contains the world point (may lie outside the grid; check with
    /// contains()).
    std::array<int, 3> voxelOf(const Vec3& world) const {
        Vec3 v = toVoxel(world);
        return {static_cast<int>(std::floor(v.x() + 0.5)), static_cast<int>(std::floor(v.y() + 0.5)),
                static_cast<int>(std::floor(v.z() + 0.5))};
    }
    /// World position of the lower corner of the grid's first voxel and the upper corner of its last.
    Vec3 lowerCorner() const { return origin - Vec3::Constant(0.5 * h); }
    Vec3 upperCorner() const { return origin + h * Vec3(dims[0] - 0.5, dims[1] - 0.5, dims[2] - 0.5); }
};

/// A grid that owns its values (x fastest, see GridSpec).
template <class T> struct Grid {
    GridSpec spec;
    BigVector<T> data; ///< large blocks on huge pages (BigAllocator)

    Grid() = default;
    explicit Grid(const GridSpec& s, T fill = T()) : spec(s), data(s.size(), fill) {}

    T& operator()(int i, int j, int k) { return data[spec.index(i, j, k)]; }
    const T& operator()(int i, int j, int k) const { return data[spec.index(i, j, k)]; }
    int nx() const { return spec.dims[0]; }
    int ny() const { return spec.dims[1]; }
    int nz() const { return spec.dims[2]; }
    std::size_t size() const { return data.size(); }
};

/// Binary voxel volume: 1 solid, 0 background.
using VoxelGrid = Grid<std::uint8_t>;
/// Scalar field on voxels, e.g. a Euclidean distance transform in voxel units.
using ScalarGrid = Grid<float>;

/// Number of solid voxels.
std::size_t countSolid(const VoxelGrid& g);

/// Bytes a grid of @p voxels voxels needs during generation (all working arrays), for the memory guard.
constexpr std::size_t kBytesPerVoxelGenerate = 14;

/// Throws std::invalid_argument when a grid of @p dims would be unreasonable (empty, over 2^31 voxels, or
/// over
/// @p memoryLimit bytes at @p bytesPerVoxel), naming @p where and the memory it would need.
void checkGridSize(const char* where, const std::array<long long, 3>& dims, std::size_t bytesPerVoxel,
                   std::size_t memoryLimit);

} // namespace mss
