// The format table (mss/io.hpp): one row per extension, and every reader and writer it names works through
// readMesh and writeSpheres.
#include "mss/io.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;
}

TEST(Formats, EachExtensionOnceLowerCaseWithItsReaderOrWriter) {
    std::set<std::string> seen;
    for (const FileFormat& f : fileFormats()) {
        const std::string ext = f.extension;
        EXPECT_TRUE(seen.insert(ext).second) << ext << " twice";
        EXPECT_EQ(ext[0], '.');
        EXPECT_EQ(fileExtension("a" + ext), ext);
        if (f.kind == FileKind::Mesh) EXPECT_NE(f.readMesh, nullptr) << ext;
        if (f.kind != FileKind::Spheres) EXPECT_EQ(f.formatSpheres, nullptr) << ext;
    }
    EXPECT_EQ(formatList(FileKind::Mesh), ".stl, .obj, .off or .ply");
    EXPECT_EQ(formatList(FileKind::Spheres, true), ".csv, .txt or .vtk");
    EXPECT_EQ(findFormat("x/G.STL", FileKind::Mesh)->extension, std::string(".stl"));
    EXPECT_EQ(findFormat("g.stl", FileKind::Spheres), nullptr);
}

TEST(Formats, EveryWriterRoundTripsThroughReadSpheres) {
    SphereSet s;
    s.centers = {Vec3(0.1, -2.5, 3.0), Vec3(1.0 / 3.0, 2e-7, -1e5)};
    s.radii = {0.25, 1.0 / 7.0};
    for (const FileFormat& f : fileFormats()) {
        if (!f.formatSpheres) continue;
        const std::string path =
            (std::filesystem::temp_directory_path() / ("mss_formats_test" + std::string(f.extension)))
                .string();
        writeSpheres(s, path);
        const SphereSet back = readSpheres(path);
        std::remove(path.c_str());
        ASSERT_EQ(back.size(), s.size()) << f.extension;
        for (std::size_t i = 0; i < s.size(); ++i) {
            EXPECT_EQ(back.centers[i], s.centers[i]) << f.extension; // 17 digits: exact
            EXPECT_EQ(back.radii[i], s.radii[i]) << f.extension;
        }
    }
}

TEST(Formats, EveryMeshReaderReadsItsFormatThroughReadMesh) {
    // a tetrahedron in each text format, and the bundled STL
    const std::map<std::string, std::string> files = {
        {".obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"},
        {".off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {".ply",
         "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float "
         "z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 "
         "0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"}};
    std::set<std::string> read;
    for (const FileFormat& f : fileFormats()) {
        if (f.kind != FileKind::Mesh) continue;
        std::string path = kData + "/cube.stl";
        if (files.count(f.extension)) {
            path = (std::filesystem::temp_directory_path() / ("mss_formats_test" + std::string(f.extension)))
                       .string();
            std::ofstream(path) << files.at(f.extension);
        }
        const TriangleMesh m = readMesh(path);
        if (files.count(f.extension))
            EXPECT_EQ(m.triangles.size(), 4u) << f.extension;
        else
            EXPECT_GT(m.triangles.size(), 12u); // the bundled cube, finely triangulated
        if (files.count(f.extension)) std::remove(path.c_str());
        read.insert(f.extension);
    }
    EXPECT_EQ(read, (std::set<std::string>{".stl", ".obj", ".off", ".ply"}));
    EXPECT_THROW(readMesh(kData + "/two_grains_labels.npy"), std::invalid_argument); // not a mesh format
}
