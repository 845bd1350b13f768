// The mesh writers, one function each; io/formats.cpp lists them. Each gives the whole file (writeMesh writes
// it atomically).
#pragma once

#include "mss/mesh.hpp"

#include <string>

namespace mss::detail {

/// .stl: binary STL (80-byte header, a facet's normal and corners in floats).
std::string formatStl(const TriangleMesh& m);
/// .obj: Wavefront OBJ, "v x y z" and "f i j k" (from 1), full precision.
std::string formatObj(const TriangleMesh& m);
/// .ply: binary little-endian PLY, double coordinates, int indices.
std::string formatPly(const TriangleMesh& m);

} // namespace mss::detail
