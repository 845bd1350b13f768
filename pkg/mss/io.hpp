// Files: every format read or written, in one table (io/formats.cpp), and the readers and writers by
// extension. A new format is one reader or writer file in io/ and one row of the table.
#pragma once

#include "mss/grid.hpp"
#include "mss/mesh.hpp"
#include "mss/spheres.hpp"
#include "mss/voxelize.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace mss {

/// What a file holds.
enum class FileKind { Mesh, Voxels, Spheres };

/// One row of the format table.
struct FileFormat {
    const char* extension; ///< lower case, with the dot: ".stl"
    FileKind kind;
    const char* description;
    /// Mesh: the reader (a regular file of this extension, not empty), else null.
    TriangleMesh (*readMesh)(const std::string& path);
    /// Spheres: the text of a sphere set in this format (writeSpheres writes it atomically), else null.
    std::string (*formatSpheres)(const SphereSet& spheres);
    /// Whether the core reads it (a voxel stack in .tif is read by the Python package, with tifffile).
    bool readByCore;
    /// Mesh: the whole file of a mesh in this format (writeMesh writes it atomically), else null.
    std::string (*formatMesh)(const TriangleMesh& mesh);
};

/// The table: every format of every kind.
const std::vector<FileFormat>& fileFormats();

/// The row of @p path's extension among formats of @p kind, or null.
const FileFormat* findFormat(const std::string& path, FileKind kind);

/// The extensions of @p kind as a list for messages (".stl, .obj, .off or .ply"); @p writable: only those
/// written.
std::string formatList(FileKind kind, bool writable = false);

/// Lower-cased extension of @p path including the dot (".stl"), or "" if none.
std::string fileExtension(const std::string& path);

/// Reads a mesh file by extension: .stl (ASCII or binary), .obj, .off, .ply (ASCII or binary). Our own
/// readers, not CGAL's: fuzzing found CGAL 5.5's OFF and PLY readers reserving gigabytes on a header's say-so
/// and running into undefined behaviour on malformed files; ours check every count against the file size.
/// Polygons with more than three corners are split into triangle fans; STL corners are merged into vertices.
/// @throws std::invalid_argument naming the file and the problem (missing, unreadable, unknown extension,
///         malformed, no triangles, non-finite coordinates).
TriangleMesh readMesh(const std::string& path);

/// Writes spheres by extension: .csv ("x,y,z,r" header and rows), .txt (YADE text clump "x y z r clumpId",
/// the format of ymport.textClumps), .vtk (legacy VTK polydata, points with a "radius" scalar, for ParaView's
/// glyphs). Full precision (17 significant digits). Written to a temporary file and renamed, so an
/// interrupted run never leaves a half-written file. @throws std::invalid_argument on an unknown extension or
/// unwritable path.
void writeSpheres(const SphereSet& s, const std::string& path);

/// The text writeSpheres writes to @p path (by its extension), for a caller that writes it itself (a batch
/// digests each grain's file as it makes it). @throws std::invalid_argument as writeSpheres.
std::string formatSpheres(const SphereSet& s, const std::string& path);

/// How formatRows writes a number.
enum class NumberText {
    Shortest,   ///< as Python's repr(float): the shortest digits that read back the same ("0.1", "100.0",
                ///< "1e-05")
    Precision17 ///< as printf's "%.17g"
};

/// Appends @p v to @p out as @p style writes it (NaN as "nan", infinities as "inf" and "-inf").
void appendNumber(std::string& out, double v, NumberText style);

/// The text of @p rows rows: each row's @p intCols integers (row-major in @p ints), then its @p cols numbers
/// (row-major in @p values), separated by @p sep, the row ended by @p end. A batch's tables (assembly.vtk,
/// contacts.csv). @throws std::invalid_argument for columns asked without their array.
std::string formatRows(const std::int64_t* ints, std::size_t intCols, const double* values, std::size_t cols,
                       std::size_t rows, NumberText style, char sep, const std::string& end);

/// A batch's assembly.txt body: for each of @p clumps clumps c, the line "#mss clump ID density 1 mass M
/// centroid X Y Z inertia XX YY ZZ XY XZ YZ" (@p heads: 10 numbers a clump, its mass properties at unit
/// density) and then a line "x y z r ID" for each sphere s of offsets[c] .. offsets[c + 1] - 1 of @p spheres
/// (@p count rows x y z r), numbers as NumberText::Shortest writes them (read back by yade_mss.readClumps,
/// and by YADE's ymport.textClumps, which skips the # lines). @throws std::invalid_argument for offsets past
/// the spheres or decreasing.
std::string formatClumpAssembly(const double* spheres, std::size_t count, const std::int64_t* offsets,
                                const std::int64_t* ids, const double* heads, std::size_t clumps);

/// Writes a mesh by extension: .stl (binary), .obj (full precision), .ply (binary little-endian, doubles),
/// atomically. @throws std::invalid_argument on a mesh validateMesh refuses, an unknown extension or an
/// unwritable path.
void writeMesh(const TriangleMesh& mesh, const std::string& path);

/// Reads spheres from CSV (x,y,z,r with optional header; CLUMP's output, Python %.18e or MATLAB %10f, CRLF
/// too), a legacy VTK file (readVtkSpheres), or a YADE text clump file
/// (whitespace-separated x y z r [clumpId], '#' comments). An integer fifth column is the clump id: a file of
/// several clumps is refused unless @p clumpId (>= 0) chooses one, so that clumps are never merged silently.
/// Other extra columns are ignored.
/// @throws std::invalid_argument naming the file and line of the problem, or the clump ids present.
SphereSet readSpheres(const std::string& path, long long clumpId = -1);

/// Reads a legacy VTK file (ASCII or BINARY) of POLYDATA points with a point array named radius (SCALARS or
/// FIELD; CLUMP's outputVTK= and our own .vtk), cells ignored. readSpheres calls it for a file that starts
/// with "# vtk". @throws std::invalid_argument saying what the file lacks (other datasets, no radius array).
SphereSet readVtkSpheres(const std::string& path);

/// Reads a 3-D boolean or integer .npy array as a binary volume: voxel (i, j, k) is a[i, j, k], so numpy's
/// first axis is x. With @p label >= 0 a voxel is solid when it equals the label (a labelled CT volume), else
/// when it is non-zero. The grid gets voxel size @p voxelSize and voxel (0, 0, 0) centred at @p origin.
/// @throws std::invalid_argument naming the file and the problem (not .npy, truncated, not 3-D, empty,
///         floating point or other unsupported dtype, label absent).
/// A labelled volume from a .npy file (integers or booleans, C or Fortran order): every label kept, for
/// findContacts. The same checks as readNpy. @throws std::invalid_argument naming the file and the problem.
LabelGrid readNpyLabels(const std::string& path, double voxelSize = 1.0, const Vec3& origin = Vec3::Zero());

VoxelGrid readNpy(const std::string& path, double voxelSize = 1.0, const Vec3& origin = Vec3::Zero(),
                  long long label = -1);

} // namespace mss
