// The one table of file formats: every extension the project reads or writes, what it holds and who reads
// or writes it. readMesh and writeSpheres dispatch through it; the command line's and the Python package's
// lists of extensions are made from it (the binding's fileFormats()). A new format: its reader or writer file
// in io/ and a row here.
#include "mss/io.hpp"
#include "mss/io/atomic_file.hpp"
#include "mss/io/input_file.hpp"
#include "mss/io/mesh_readers.hpp"
#include "mss/io/mesh_writers.hpp"
#include "mss/io/sphere_writers.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace mss {

namespace {

using K = FileKind;

// extension, kind, description, mesh reader, sphere writer, read by the core, mesh writer
const std::vector<FileFormat> kFormats = {
    {".stl", K::Mesh, "STL, ASCII or binary (corners merged into vertices)", detail::readStl, nullptr, true,
     detail::formatStl},
    {".obj", K::Mesh, "Wavefront OBJ (polygons split into fans)", detail::readObj, nullptr, true,
     detail::formatObj},
    {".off", K::Mesh, "Object File Format", detail::readOff, nullptr, true, nullptr},
    {".ply", K::Mesh, "Polygon File Format, ASCII or binary", detail::readPly, nullptr, true,
     detail::formatPly},
    {".npy", K::Voxels, "numpy array, 3-D, boolean or integer (labels)", nullptr, nullptr, true, nullptr},
    {".tif", K::Voxels, "TIFF stack, as CT software exports it (the Python package reads it)", nullptr,
     nullptr, false, nullptr},
    {".tiff", K::Voxels, "TIFF stack (as .tif)", nullptr, nullptr, false, nullptr},
    {".csv", K::Spheres, "x,y,z,r (CLUMP's columns; its Python and MATLAB forms are read too)", nullptr,
     detail::formatCsv, true, nullptr},
    {".txt", K::Spheres, "YADE text clump: x y z r clumpId (ymport.textClumps)", nullptr,
     detail::formatYadeText, true, nullptr},
    {".vtk", K::Spheres, "legacy VTK points with a radius array (ParaView's glyphs; CLUMP's outputVTK=)",
     nullptr, detail::formatVtk, true, nullptr},
};

} // namespace

const std::vector<FileFormat>& fileFormats() {
    return kFormats;
}

std::string fileExtension(const std::string& path) {
    const auto slash = path.find_last_of("/\\");
    const auto dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

const FileFormat* findFormat(const std::string& path, FileKind kind) {
    const std::string ext = fileExtension(path);
    for (const FileFormat& f : kFormats)
        if (f.kind == kind && ext == f.extension) return &f;
    return nullptr;
}

std::string formatList(FileKind kind, bool writable) {
    std::vector<std::string> exts;
    for (const FileFormat& f : kFormats)
        if (f.kind == kind && f.readByCore && (!writable || f.formatSpheres || f.formatMesh))
            exts.push_back(f.extension);
    std::string out;
    for (std::size_t i = 0; i < exts.size(); ++i)
        out += (i == 0 ? "" : i + 1 == exts.size() ? " or " : ", ") + exts[i];
    return out;
}

namespace {

/// A face repeated (the same three corners, in any order) counts twice in every winding number and meets all
/// its copies in every query: 10^5 copies of one face ran for hours. A mesh's faces are distinct.
void refuseRepeatedFaces(const TriangleMesh& mesh, const std::string& path) {
    std::vector<std::pair<std::array<int, 3>, std::size_t>> keys(mesh.triangles.size());
    for (std::size_t i = 0; i < keys.size(); ++i) {
        std::array<int, 3> t = mesh.triangles[i];
        std::sort(t.begin(), t.end());
        keys[i] = {t, i};
    }
    std::sort(keys.begin(), keys.end());
    std::size_t repeated = 0, first = 0, again = 0;
    for (std::size_t k = 1; k < keys.size(); ++k)
        if (keys[k].first == keys[k - 1].first && keys[k].first[0] != keys[k].first[1] &&
            keys[k].first[1] != keys[k].first[2] && repeated++ == 0) {
            first = keys[k - 1].second;
            again = keys[k].second;
        }
    if (repeated > 0)
        detail::fail(
            path, std::to_string(repeated) + " faces repeat another (face " + std::to_string(again) +
                      " has the corners of face " + std::to_string(first) +
                      "): a mesh's faces are distinct; remove the copies (MeshLab: Remove Duplicate Faces)");
}

} // namespace

TriangleMesh readMesh(const std::string& path) {
    detail::requireRegularFile("readMesh", path); // first: a directory or device says what it is
    const FileFormat* f = findFormat(path, FileKind::Mesh);
    if (!f)
        detail::fail(path, "unknown mesh extension '" + fileExtension(path) + "' (expected " +
                               formatList(FileKind::Mesh) + ")");
    std::ifstream probe(path, std::ios::binary | std::ios::ate);
    if (!probe) detail::fail(path, "cannot open file");
    if (probe.tellg() <= 0) detail::fail(path, "file is empty");
    probe.close();
    TriangleMesh mesh = f->readMesh(path);
    validateMesh(mesh, "readMesh: " + path);
    refuseRepeatedFaces(mesh, path);
    return mesh;
}

void writeMesh(const TriangleMesh& mesh, const std::string& path) {
    validateMesh(mesh, "writeMesh");
    const FileFormat* f = findFormat(path, FileKind::Mesh);
    if (!f || !f->formatMesh)
        throw std::invalid_argument("writeMesh: " + path + ": unknown extension '" + fileExtension(path) +
                                    "' (expected " + formatList(FileKind::Mesh, true) + ")");
    detail::writeFileAtomically("writeMesh", path, f->formatMesh(mesh));
}

} // namespace mss
