#include "mss/core/index_table.hpp"
#include "mss/io.hpp"
#include "mss/io/mesh_readers.hpp"
#include "mss/mesh.hpp"
#include "mss/spheres.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <sys/stat.h>
#include <unistd.h>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;

std::string tempPath(const std::string& name) {
    return ::testing::TempDir() + "/mss_io_" + std::to_string(::getpid()) + "_" + name;
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

void expectError(const std::function<void()>& f, const std::string& fragment) {
    try {
        f();
        FAIL() << "no exception, expected one mentioning '" << fragment << "'";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

void writeNpy(const std::string& path, const std::string& descr, const std::string& shape,
              const std::vector<char>& data, bool fortran = false) {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
                         ", 'shape': (" + shape + "), }";
    while ((10 + header.size() + 1) % 64) header += ' ';
    header += '\n';
    std::ofstream out(path, std::ios::binary);
    out.write("\x93NUMPY\x01\x00", 8);
    const unsigned short len = static_cast<unsigned short>(header.size());
    out.put(char(len & 0xff));
    out.put(char(len >> 8));
    out << header;
    out.write(data.data(), std::streamsize(data.size()));
}
} // namespace

TEST(MeshIo, AsciiAndBinaryStlAgree) {
    const TriangleMesh femur = readMesh(kData + "/human_femur.stl"); // ASCII
    const MeshInfo info = analyzeMesh(femur);
    EXPECT_EQ(info.triangles, 13752u);
    EXPECT_TRUE(info.closed);
    EXPECT_NEAR(info.signedVolume, 125621.0, 1.0); // data/README.md
    // write it as binary STL and read it back
    const std::string bin = tempPath("femur_bin.stl");
    {
        std::ofstream out(bin, std::ios::binary);
        char header[80] = "binary";
        out.write(header, 80);
        const std::uint32_t n = std::uint32_t(femur.triangles.size());
        out.write(reinterpret_cast<const char*>(&n), 4);
        for (const auto& t : femur.triangles) {
            float rec[12] = {0, 0, 0};
            for (int c = 0; c < 3; ++c)
                for (int a = 0; a < 3; ++a) rec[3 + 3 * c + a] = float(femur.vertices[t[c]][a]);
            out.write(reinterpret_cast<const char*>(rec), 48);
            out.write("\0\0", 2);
        }
    }
    const MeshInfo binInfo = analyzeMesh(readMesh(bin));
    EXPECT_EQ(binInfo.triangles, info.triangles);
    EXPECT_EQ(binInfo.vertices, info.vertices); // corners merged back into shared vertices
    EXPECT_NEAR(binInfo.signedVolume, info.signedVolume, 1e-4 * info.signedVolume);
    std::remove(bin.c_str());
}

TEST(MeshIo, StlCornersMergeInOrderOfFirstAppearance) {
    // the STL reader's vertex table (open addressing, sized for a quarter of the corners, grown as it fills):
    // -0 and 0 are one position, vertices come in order of first appearance, and a strip of 3000 triangles
    // (about 6000 vertices of 9000 corners: the table grows) merges exactly as a plain map does
    const std::string path = tempPath("merge.stl");
    std::vector<std::array<Vec3, 3>> facets{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)},
                                            {Vec3(-0.0, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}};
    for (int t = 0; t < 3000; ++t)
        facets.push_back({Vec3(t, 2, 0.5 * (t % 3)), Vec3(t + 1, 2, 0.5 * ((t + 1) % 3)), Vec3(t, 3, 0)});
    {
        std::ofstream out(path);
        out << std::setprecision(17) << "solid m\n";
        for (const auto& f : facets) {
            out << "facet normal 0 0 0\nouter loop\n";
            for (const Vec3& v : f) out << "vertex " << v.x() << " " << v.y() << " " << v.z() << "\n";
            out << "endloop\nendfacet\n";
        }
        out << "endsolid m\n";
    }
    const TriangleMesh m = readMesh(path);
    std::remove(path.c_str());
    std::map<std::array<double, 3>, int> seen;
    std::vector<Vec3> order;
    ASSERT_EQ(m.triangles.size(), facets.size());
    for (std::size_t t = 0; t < facets.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const Vec3& v = facets[t][std::size_t(c)];
            const std::array<double, 3> key{v.x() + 0.0, v.y() + 0.0, v.z() + 0.0}; // -0 + 0 is 0
            auto [it, added] = seen.emplace(key, int(order.size()));
            if (added) order.push_back(v);
            EXPECT_EQ(m.triangles[t][std::size_t(c)], it->second) << "triangle " << t << " corner " << c;
        }
    ASSERT_EQ(m.vertices.size(), order.size());
    EXPECT_EQ(m.triangles[1][0], 0); // -0 merged with 0
    for (std::size_t v = 0; v < order.size(); ++v) EXPECT_EQ(m.vertices[v], order[v]);
}

TEST(IndexTable, IndicesInOrderOfAdditionThroughCollisionsAndGrowth) {
    // the table under the STL reader's vertex merging and the candidates' positions seen: 5000 keys whose
    // hashes collide in runs of 7 (long probes), each added once and then found at its index, the table grown
    // from 1024 slots several times; a second add of a key finds it and adds nothing
    std::vector<int> keys;
    mss::detail::IndexTable table;
    auto hash = [](int k) { return std::uint64_t(k / 7); };
    auto findOrAdd = [&](int k) {
        return table.findOrAdd(
            hash(k), keys.size(), [&](int q) { return keys[std::size_t(q)] == k; },
            [&](int q) { return hash(keys[std::size_t(q)]); });
    };
    for (int n = 0; n < 5000; ++n) {
        const int k = (n * 7919) % 5003; // distinct, in a scrambled order
        ASSERT_EQ(findOrAdd(k), -1) << n;
        keys.push_back(k);
    }
    for (std::size_t n = 0; n < keys.size(); ++n) ASSERT_EQ(findOrAdd(keys[n]), int(n));
    EXPECT_EQ(keys.size(), 5000u);
    EXPECT_EQ(table.used(), keys.size());
    mss::detail::IndexTable filled(10); // too small: addAll grows it, each key recorded once
    filled.addAll(keys.size(), [&](int q) { return hash(keys[std::size_t(q)]); });
    EXPECT_EQ(filled.used(), keys.size());
    for (std::size_t n = 0; n < keys.size(); n += 97)
        EXPECT_EQ(filled.findOrAdd(
                      hash(keys[n]), keys.size(), [&](int q) { return keys[std::size_t(q)] == keys[n]; },
                      [&](int q) { return hash(keys[std::size_t(q)]); }),
                  int(n));
}

TEST(MeshIo, ObjOffPlyAscii) {
    const std::string obj = tempPath("tet.obj"), off = tempPath("tet.off"), ply = tempPath("tet.ply");
    writeText(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    writeText(off, "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    writeText(
        ply,
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
        "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    for (const auto& p : {obj, off, ply}) {
        const MeshInfo i = analyzeMesh(readMesh(p));
        EXPECT_EQ(i.triangles, 4u) << p;
        EXPECT_TRUE(i.closed) << p;
        EXPECT_NEAR(i.signedVolume, 1.0 / 6.0, 1e-12) << p;
        std::remove(p.c_str());
    }
}

TEST(MeshIo, OffHeaderPrefixes) {
    // 4OFF: homogeneous coordinates (the bug: w was ignored, the mesh read twice its size); nOFF of another
    // dimension and unknown prefixes refused; COFF's colours skipped
    const std::string p = tempPath("pre.off");
    const std::string faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    writeText(p, "4OFF\n4 4 0\n0 0 0 2\n2 0 0 2\n0 2 0 2\n0 0 2 2\n" + faces);
    EXPECT_NEAR(analyzeMesh(readMesh(p)).signedVolume, 1.0 / 6.0, 1e-12);
    writeText(p, "COFF\n4 4 0\n0 0 0 1 0 0 1\n1 0 0 1 0 0 1\n0 1 0 1 0 0 1\n0 0 1 1 0 0 1\n" + faces);
    EXPECT_NEAR(analyzeMesh(readMesh(p)).signedVolume, 1.0 / 6.0, 1e-12);
    writeText(p, "nOFF 3\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + faces);
    EXPECT_NEAR(analyzeMesh(readMesh(p)).signedVolume, 1.0 / 6.0, 1e-12);
    for (const std::string& bad :
         {std::string("4OFF\n4 4 0\n0 0 0 0\n1 0 0 1\n0 1 0 1\n0 0 1 1\n") + faces,
          std::string("nOFF\n4\n4 4 0\n0 0 0 0\n") + faces, std::string("XOFF\n4 4 0\n") + faces}) {
        writeText(p, bad);
        EXPECT_THROW(readMesh(p), std::invalid_argument) << bad;
    }
    std::remove(p.c_str());
}

TEST(MeshIo, ObjIndexFormsAndBinaryPly) {
    const std::string obj = tempPath("tet2.obj"), ply = tempPath("tet_bin.ply");
    // "i/t/n" and "i//n" forms and negative (relative) indices, a quad split into two triangles
    writeText(obj, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nvt 0 0\nvn 0 0 1\n"
                   "f 1/1/1 4/1/1 3//1 2//1\nf -5 -4 -1\nf 2 3 5\nf 3 4 5\nf 4 1 5\n");
    const MeshInfo a = analyzeMesh(readMesh(obj));
    EXPECT_EQ(a.triangles, 6u);
    EXPECT_TRUE(a.closed);
    EXPECT_NEAR(a.signedVolume, 1.0 / 3.0, 1e-12); // a pyramid: base 1, height 1
    std::string bin =
        "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nelement face 4\nproperty list uchar int vertex_indices\n"
        "end_header\n";
    const float v[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (const auto& p : v) {
        bin.append(reinterpret_cast<const char*>(p), 12);
        bin.push_back('\x7f');
    }
    const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (const auto& t : f) {
        bin.push_back('\x03');
        bin.append(reinterpret_cast<const char*>(t), 12);
    }
    writeText(ply, bin);
    const MeshInfo b = analyzeMesh(readMesh(ply));
    EXPECT_EQ(b.triangles, 4u);
    EXPECT_NEAR(b.signedVolume, 1.0 / 6.0, 1e-7);
    writeText(ply, bin.substr(0, bin.size() - 5)); // cut short
    expectError([&] { readMesh(ply); }, "ends early");
    std::remove(obj.c_str());
    std::remove(ply.c_str());
}

namespace {
/// @p m as ASCII STL facets (no header), at full precision.
std::string asciiFacets(const TriangleMesh& m, std::size_t from, std::size_t to) {
    std::ostringstream os;
    os << std::setprecision(17);
    for (std::size_t t = from; t < to; ++t) {
        os << "  facet normal 0 0 1\n    outer loop\n";
        for (int c : m.triangles[t]) {
            const Vec3& v = m.vertices[std::size_t(c)];
            os << "      vertex " << v.x() << ' ' << v.y() << ' ' << v.z() << "\n";
        }
        os << "    endloop\n  endfacet\n";
    }
    return os.str();
}
} // namespace

// Files of 1 MB or more are parsed in two parts in parallel: the mesh must be exactly the one-part parse's,
// a fault in the second part must be reported at its line, and a split that lands inside a solid's name must
// not change the result.
TEST(MeshIo, LargeAsciiStlReadsAsInOnePart) {
    const TriangleMesh femur = readMesh(kData + "/human_femur.stl"); // 2.7 MB: read in two parts
    const std::size_t n = femur.triangles.size();
    const std::string p = tempPath("large.stl");
    const std::string all = "solid a\n" + asciiFacets(femur, 0, n) + "endsolid a\n";
    ASSERT_GT(all.size(), std::size_t(1) << 20);
    writeText(p, all);
    const TriangleMesh back = readMesh(p);
    ASSERT_EQ(back.vertices.size(), femur.vertices.size());
    ASSERT_EQ(back.triangles, femur.triangles); // the same vertex numbering: merged in file order
    for (std::size_t v = 0; v < femur.vertices.size(); ++v) ASSERT_EQ(back.vertices[v], femur.vertices[v]);

    // a bad number three quarters of the way in: reported at its line
    std::string bad = all;
    const std::size_t at = bad.find("vertex ", bad.size() * 3 / 4);
    bad.replace(at + 7, 1, "zz");
    const long line = 1 + std::count(bad.begin(), bad.begin() + long(at), '\n');
    writeText(p, bad);
    expectError([&] { readMesh(p); }, "line " + std::to_string(line) + ":");

    // two solids, the second named "b endfacet c", with the middle of the file just before that name's
    // "endfacet": the second part then starts inside the name and fails, and one part reads it all
    const std::string head = "solid a\n" + asciiFacets(femur, 0, n / 2) + "endsolid a\n";
    const std::string odd = "solid b endfacet c\n";
    std::string tail = asciiFacets(femur, n / 2, n - 200) + "endsolid b\n";
    const std::size_t total = 2 * (head.size() + 8); // the middle: inside "solid b " of the odd line
    ASSERT_LT(head.size() + odd.size() + tail.size(), total);
    tail.append(total - head.size() - odd.size() - tail.size(), ' ');
    writeText(p, head + odd + tail);
    const TriangleMesh two = readMesh(p);
    EXPECT_EQ(two.triangles.size(), n - 200);
    EXPECT_TRUE(std::equal(two.triangles.begin(), two.triangles.end(), femur.triangles.begin()));
    std::remove(p.c_str());
}

/// detail::parseDouble must give what std::from_chars gives (after an optional '+'), bit for bit, and
/// refuse what it refuses: its fast path (Clinger's) on plain decimals, from_chars on the rest.
TEST(MeshIo, NumbersParseExactlyAsFromChars) {
    auto check = [](const std::string& w) {
        double fast = 0.0, ref = 0.0;
        const bool ok = detail::parseDouble(w.data(), w.data() + w.size(), fast);
        const char* b = w.data() + (!w.empty() && w[0] == '+');
        const auto r = std::from_chars(b, w.data() + w.size(), ref);
        const bool refOk = !w.empty() && r.ec == std::errc() && r.ptr == w.data() + w.size();
        ASSERT_EQ(ok, refOk) << "'" << w << "'";
        if (ok)
            ASSERT_EQ(std::memcmp(&fast, &ref, sizeof(double)), 0)
                << "'" << w << "': " << fast << " vs " << ref;
    };
    // the cases, '|' between them (the empty one and those with spaces included)
    const std::string list =
        "0|-0|+0|-0.0|1|-1.5|206.335|-149.97|0.585458|-0.0105082|1e22|1e23|1e-22|1e-23|"
        "9007199254740992|9007199254740993|90071992547409921|1234567890123456789|"
        "12345678901234567890|0.1|0.3|2.2250738585072014e-308|4.9e-324|1.7976931348623157e308|"
        "1e309|1.|.5|-.5|1e|1e+|1e-|1e+5|1E5|1.5e-3|+-5|--5|-|+||inf|-inf|nan|0x1p3|1,5|1.5.5|"
        "1e5e5|00012.5000|1e0000000000000000000001|123.456e-20|123.456e20|5e-0| 1|1 ";
    std::vector<std::string> cases(1);
    for (char c : list) {
        if (c == '|')
            cases.emplace_back();
        else
            cases.back() += c;
    }
    for (const std::string& w : cases) check(w);
    std::mt19937_64 rng(12345);
    for (int q = 0; q < 200000; ++q) {
        // random plain decimals: up to 20 digits, a point somewhere or none, an exponent or none
        std::string w = rng() % 2 ? "-" : "";
        const int digits = 1 + int(rng() % 20), point = int(rng() % (digits + 1));
        for (int d = 0; d < digits; ++d) {
            if (d == point && d > 0) w += '.';
            w += char('0' + rng() % 10);
        }
        if (rng() % 3 == 0) w += "e" + std::string(rng() % 2 ? "-" : "") + std::to_string(rng() % 40);
        check(w);
    }
}

TEST(MeshIo, BadFilesGetClearErrors) {
    const std::string p = tempPath("bad.stl");
    writeText(p, "");
    expectError([&] { readMesh(p); }, "empty");
    std::string bin(84 + 50 * 3, '\0');
    bin[80] = 5; // says 5 triangles, has 3
    writeText(p, bin);
    expectError([&] { readMesh(p); }, "says 5 triangles");
    writeText(p, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 zz\n");
    expectError([&] { readMesh(p); }, "line 5");
    writeText(p, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 nan\nvertex 0 1 "
                 "0\nendloop\nendfacet\n");
    expectError([&] { readMesh(p); }, "non-finite");
    std::remove(p.c_str());
    expectError([&] { readMesh(tempPath("missing.stl")); }, "cannot open");
    expectError([&] { readMesh(tempPath("x.xyz")); }, "unknown mesh extension");
    const std::string dir = tempPath("folder.stl"); // a directory with a mesh's name
    std::filesystem::create_directories(dir);
    expectError([&] { readMesh(dir); }, "not a regular file (a directory)");
    std::filesystem::remove(dir);
    // a directory or device is named as such whatever its name (it was 'unknown mesh extension')
    expectError([&] { readMesh("/dev/zero"); }, "/dev/zero: not a regular file (a character device)");
    // the bug: coordinates of 1e308 voxelised at 1e306 a voxel and gave a 'grain' of D 0.9997, the mass
    // properties overflowing; refused with the bound
    writeText(tempPath("huge.obj"), "v 0 0 0\nv 1e308 0 0\nv 0 1e308 0\nv 0 0 1e308\nf 1 3 2\nf 1 2 4\nf 1 4 "
                                    "3\nf 2 3 4\n");
    expectError([&] { readMesh(tempPath("huge.obj")); },
                "has a coordinate of 1e+308, too large (at most 1e+60");
    std::remove(tempPath("huge.obj").c_str());
}

TEST(SpheresIo, RoundTripAtFullPrecision) {
    SphereSet s;
    s.add(Vec3(0.1, -2.0 / 3.0, 1e-7), 0.123456789012345678);
    s.add(Vec3(1e5, 2, 3), 4.5);
    for (const std::string ext : {".csv", ".txt"}) {
        const std::string p = tempPath("s" + ext);
        writeSpheres(s, p);
        const SphereSet r = readSpheres(p);
        ASSERT_EQ(r.size(), 2u);
        EXPECT_EQ(r.centers[0], s.centers[0]) << ext;
        EXPECT_EQ(r.radii[0], s.radii[0]) << ext;
        std::remove(p.c_str());
    }
    const std::string vtk = tempPath("s.vtk");
    writeSpheres(s, vtk);
    std::ifstream in(vtk);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(all.find("POINTS 2 double"), std::string::npos);
    EXPECT_NE(all.find("SCALARS radius double"), std::string::npos);
    std::remove(vtk.c_str());
}

TEST(SpheresIo, ReadsClumpCsvAndYadeText) {
    const std::string csv = tempPath("clump.csv"), txt = tempPath("yade.txt");
    writeText(csv, "x,y,z,r\n1,2,3,0.5\n-1,-2,-3,0.25\n");
    writeText(txt, "# comment\n1 2 3 0.5 0\n4 5 6 0.75 0\n");
    EXPECT_EQ(readSpheres(csv).size(), 2u);
    EXPECT_EQ(readSpheres(txt).radii[1], 0.75);
    writeText(csv, "x,y,z,r\n1,2,3,-0.5\n");
    expectError([&] { readSpheres(csv); }, "radius");
    writeText(csv, "1,2,3,abc\n");
    expectError([&] { readSpheres(csv); }, "line 1");
    writeText(csv, "x,y,z,r\n");
    expectError([&] { readSpheres(csv); }, "no spheres");
    std::remove(csv.c_str());
    std::remove(txt.c_str());
}

TEST(SpheresIo, UnwritablePathIsAnError) {
    SphereSet s;
    s.add(Vec3(0, 0, 0), 1);
    expectError([&] { writeSpheres(s, "/nonexistent-dir/x.csv"); }, "cannot write");
    expectError([&] { writeSpheres(s, tempPath("x.doc")); }, "unknown extension");
}

TEST(Npy, ReadsCOrderAndFortranOrderAndLabels) {
    const std::string p = tempPath("v.npy");
    // shape (2, 3, 4): a[i, j, k] = i * 100 + j * 10 + k, so only a[1, 2, 3] == 123
    std::vector<char> c(24 * 2);
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 4; ++k) {
                const std::int16_t v = std::int16_t(i * 100 + j * 10 + k);
                std::memcpy(&c[2 * (k + 4 * (j + 3 * i))], &v, 2);
            }
    writeNpy(p, "<i2", "2, 3, 4", c);
    const VoxelGrid v = readNpy(p, 0.5, Vec3(1, 1, 1), 123);
    EXPECT_EQ(v.nx(), 2);
    EXPECT_EQ(v.nz(), 4);
    EXPECT_EQ(countSolid(v), 1u);
    EXPECT_EQ(v(1, 2, 3), 1);
    EXPECT_EQ(v.spec.h, 0.5);
    std::vector<char> f(24 * 2);
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 4; ++k) {
                const std::int16_t val = std::int16_t(i * 100 + j * 10 + k);
                std::memcpy(&f[2 * (i + 2 * (j + 3 * k))], &val, 2);
            }
    writeNpy(p, "<i2", "2, 3, 4", f, true);
    EXPECT_EQ(readNpy(p, 1.0, Vec3::Zero(), 123)(1, 2, 3), 1);
    // without a label these 23 grains would merge into one solid: refused, naming the labels present
    expectError([&] { readNpy(p); }, "holds 23 labels (1, 2, 3,");
    std::remove(p.c_str());
}

TEST(SpheresIo, SeveralClumpsAreNeverMerged) {
    const std::string p = tempPath("clumps.txt");
    {
        std::ofstream o(p);
        o << "#format x_y_z_r_clumpId\n0\t0\t0\t1\t4\n1\t0\t0\t1\t4\n9\t0\t0\t2\t12\n";
    }
    expectError([&] { readSpheres(p); }, "holds 2 clumps (ids 4, 12): choose one");
    EXPECT_EQ(readSpheres(p, 4).size(), 2u);
    EXPECT_EQ(readSpheres(p, 12).radii[0], 2.0);
    expectError([&] { readSpheres(p, 5); }, "no clump with id 5 (clump ids: 4, 12)");
    std::remove(p.c_str());
}

TEST(Npy, BadArraysGetClearErrors) {
    const std::string p = tempPath("bad.npy");
    writeNpy(p, "<f4", "2, 2, 2", std::vector<char>(32));
    expectError([&] { readNpy(p); }, "not boolean or integer");
    writeNpy(p, "|b1", "4, 4", std::vector<char>(16, 1));
    expectError([&] { readNpy(p); }, "3-D");
    writeNpy(p, "|b1", "4, 0, 4", {});
    expectError([&] { readNpy(p); }, "empty");
    writeNpy(p, "|b1", "4, 4, 4", std::vector<char>(10, 1));
    expectError([&] { readNpy(p); }, "truncated");
    writeNpy(p, "|b1", "2, 2, 2", std::vector<char>(8, 0));
    expectError([&] { readNpy(p); }, "no solid voxel");
    writeText(p, "not numpy at all");
    expectError([&] { readNpy(p); }, "magic");
    std::remove(p.c_str());
}

// Big-endian arrays (NumPy writes them as '>i2' etc.) were refused; their bytes are swapped now: the same
// labels as the little-endian file of the same values (258 = 0x0102 reads as 513 unswapped).
TEST(Npy, BigEndianArraysReadAsTheirValues) {
    const std::string p = tempPath("big.npy");
    for (const char* descr : {">i2", ">u4", ">i8"}) {
        const int width = descr[2] - '0';
        std::vector<char> little(24 * width, 0), big(24 * width, 0);
        for (int q = 0; q < 24; ++q) {
            const std::uint64_t v = q % 5 == 0 ? 258 : 1;
            for (int b = 0; b < width && b < 8; ++b) {
                little[q * width + b] = char((v >> (8 * b)) & 0xff);
                big[q * width + (width - 1 - b)] = char((v >> (8 * b)) & 0xff);
            }
        }
        writeNpy(p, std::string("<") + (descr + 1), "2, 3, 4", little);
        const VoxelGrid a = readNpy(p, 1.0, Vec3::Zero(), 258);
        writeNpy(p, descr, "2, 3, 4", big);
        const VoxelGrid b = readNpy(p, 1.0, Vec3::Zero(), 258);
        EXPECT_EQ(countSolid(a), 5u) << descr;
        EXPECT_EQ(a.data, b.data) << descr;
    }
    std::remove(p.c_str());
}

// The bug: a shape that the file cannot hold was judged against the memory limit ('would need 9.31e+05 GiB
// ... choose a coarser resolution', for a file of 64 bytes), and a shape overflowing 64 bits wrapped around.
TEST(Npy, ShapesBeyondTheFileAreRefusedBeforeAnythingElse) {
    const std::string p = tempPath("lying.npy");
    writeNpy(p, "|u1", "100000, 100000, 100000", std::vector<char>(64, 1));
    expectError([&] { readNpy(p); }, "needs 1e+15 bytes after the header, more than the file holds (64)");
    writeNpy(p, "<i8", "4294967296, 4294967296, 4294967296", std::vector<char>(64, 1));
    expectError([&] { readNpy(p); }, "more than the file holds (64)");
    writeNpy(p, "|u1", "4, -4, 4", std::vector<char>(64, 1));
    expectError([&] { readNpy(p); }, "a negative size: -4");
    std::remove(p.c_str());
}

// The bug: a header of ~26 KB overflowed the stack in std::regex (exit 139). Headers are scanned now, and one
// longer than NumPy ever writes is refused before it is read.
TEST(Npy, test_long_header_overflowed_the_stack) {
    const std::string p = tempPath("long.npy");
    for (std::size_t pad : {30000u, 60000u}) {
        std::string header =
            "{'descr': '|b1', 'fortran_order': False, 'shape': (2, 2, 2), }" + std::string(pad, ' ');
        header += '\n';
        std::ofstream out(p, std::ios::binary);
        out.write("\x93NUMPY\x01\x00", 8);
        out.put(char(header.size() & 0xff));
        out.put(char((header.size() >> 8) & 0xff));
        out << header << std::string(8, '\1');
        out.close();
        EXPECT_EQ(readNpy(p)(1, 1, 1), 1); // long, but a header: read
    }
    { // version 2: a length of 16 MB, refused by its size
        std::ofstream out(p, std::ios::binary);
        out.write("\x93NUMPY\x02\x00", 8);
        const std::uint32_t len = 1u << 24;
        out.write(reinterpret_cast<const char*>(&len), 4);
        out << std::string(len, ' ');
    }
    expectError([&] { readNpy(p); }, "at most 65536");
    std::remove(p.c_str());
}

TEST(Npy, HeadersOfEitherQuoteAndMalformedOnes) {
    const std::string p = tempPath("quotes.npy");
    writeNpy(p, "|b1", "2, 2, 2", std::vector<char>(8, 1));
    std::string text;
    {
        std::ifstream in(p, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::string dq = text;
    for (char& c : dq)
        if (c == '\'') c = '"';
    writeText(p, dq);
    EXPECT_EQ(readNpy(p)(0, 0, 0), 1);
    for (const char* bad : {"'shape': 2, 2, 2", "'shape': (2, 2, x)", "'shape': (2, 2, 2, 2)"}) {
        std::string t = text;
        const std::size_t a = t.find("'shape'"), b = t.find(')', a);
        t.replace(a, b - a + 1, bad);
        writeText(p, t);
        expectError([&] { readNpy(p); }, "readNpy: " + p);
    }
    std::remove(p.c_str());
}

// The bug: a FIFO as input hung generate, info and compare; /dev/zero as a sphere file read until memory ran
// out.
TEST(Files, test_fifo_and_devices_hung_the_readers) {
    const std::string fifo = tempPath("pipe.stl");
    std::remove(fifo.c_str());
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    expectError([&] { readMesh(fifo); }, "not a regular file (a FIFO)");
    const std::string fifoNpy = tempPath("pipe.npy");
    std::remove(fifoNpy.c_str());
    ASSERT_EQ(::mkfifo(fifoNpy.c_str(), 0600), 0);
    expectError([&] { readNpy(fifoNpy); }, "not a regular file (a FIFO)");
    const std::string fifoCsv = tempPath("pipe.csv");
    std::remove(fifoCsv.c_str());
    ASSERT_EQ(::mkfifo(fifoCsv.c_str(), 0600), 0);
    expectError([&] { readSpheres(fifoCsv); }, "not a regular file (a FIFO)");
    expectError([&] { readSpheres("/dev/zero"); }, "not a regular file (a character device)");
    for (const std::string& f : {fifo, fifoNpy, fifoCsv}) std::remove(f.c_str());
}

TEST(SpheresIo, LegacyVtkAsciiBinaryAndWhatItCannotRead) {
    // CLUMP's outputVTK= (ASCII, no VERTICES) and our own .vtk (VERTICES)
    const SphereSet fa = readSpheres(kData + "/clump/FA_ellipsoid_N10_min.vtk");
    const SphereSet faText = readSpheres(kData + "/clump/FA_ellipsoid_N10_min.txt");
    ASSERT_EQ(fa.size(), 10u);
    for (std::size_t i = 0; i < fa.size(); ++i) {
        EXPECT_NEAR(fa.radii[i], faText.radii[i], 1e-6 * faText.radii[i]); // float in the VTK file
        EXPECT_NEAR((fa.centers[i] - faText.centers[i]).norm(), 0.0, 1e-6);
    }
    SphereSet s;
    s.add(Vec3(1, 2, 3), 0.5);
    s.add(Vec3(-1, 0.25, 7), 1.5);
    const std::string ours = tempPath("ours.vtk");
    writeSpheres(s, ours);
    const SphereSet back = readSpheres(ours);
    EXPECT_EQ(back.centers, s.centers);
    EXPECT_EQ(back.radii, s.radii);
    // BINARY: big-endian float points and double radii
    const SphereSet bin = readSpheres(kData + "/binary_spheres.vtk");
    ASSERT_EQ(bin.size(), 3u);
    EXPECT_EQ(bin.centers[2], Vec3(0, 2, 0));
    EXPECT_EQ(bin.radii[1], 0.6);
    const std::string p = tempPath("bad.vtk");
    auto write = [&](const std::string& text) {
        std::ofstream o(p, std::ios::binary);
        o << text;
    };
    write("# vtk DataFile Version 3.0\nx\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n0 0 0\n");
    expectError([&] { readSpheres(p); }, "only POLYDATA point sets are read");
    write("# vtk DataFile Version 3.0\nx\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 1 1\n"
          "POINT_DATA 2\nSCALARS size float 1\nLOOKUP_TABLE default\n1 2\n");
    expectError([&] { readSpheres(p); }, "no point array named radius (arrays: size)");
    write("# vtk DataFile Version 3.0\nx\nBINARY\nDATASET POLYDATA\nPOINTS 1000 double\n1234");
    expectError([&] { readSpheres(p); }, "3000 values announced, more than the file holds");
    std::remove(p.c_str());
    std::remove(ours.c_str());
}

TEST(SpheresIo, ClumpMatlabFormatWithCrlf) {
    // CLUMP's MATLAB version: dlmwrite(..., '%10f'): padded fixed-point numbers, here with CRLF line ends
    const std::string p = tempPath("matlab.txt");
    {
        std::ofstream o(p, std::ios::binary);
        o << " -1.800000, -0.000000,  0.000000,  0.200000\r\n  0.600000,  1.250000, -2.000000,  0.824924\r\n";
    }
    const SphereSet s = readSpheres(p);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.centers[1], Vec3(0.6, 1.25, -2.0));
    EXPECT_EQ(s.radii[1], 0.824924);
    std::remove(p.c_str());
}

// The bugs: the first sphere row was dropped when it began with a UTF-8 BOM, nan, inf or Infinity (taken for
// a header); clump ids 1.5 / 2.5, -1 / -2 and 1e16 were merged with the spheres without an id.
TEST(SphereIo, test_first_row_dropped_and_ids_merged) {
    const std::string p = tempPath("rows.txt");
    writeText(p, "\xEF\xBB\xBF"
                 "1 2 3 0.5\n4 5 6 0.25\n");
    EXPECT_EQ(readSpheres(p).size(), 2u);
    writeText(p, "\xEF\xBB\xBF"
                 "x,y,z,r\n1,2,3,0.5\n");
    EXPECT_EQ(readSpheres(p).size(), 1u); // a header after the mark is still a header
    for (const char* first : {"nan", "inf", "Infinity", "-inf"}) {
        writeText(p, std::string(first) + " 2 3 0.5\n4 5 6 0.25\n");
        expectError([&] { readSpheres(p); }, "line 1: '" + std::string(first) + "' is not a finite number");
    }
    writeText(p, "1 2 3 nan\n");
    expectError([&] { readSpheres(p); }, "is not a finite number");
    for (const char* id : {"1.5", "-1", "1e16", "abc"}) {
        writeText(p, "1 2 3 0.5 " + std::string(id) + "\n4 5 6 0.25 " + std::string(id) + "\n");
        expectError([&] { readSpheres(p); }, "line 1: clump id '" + std::string(id) + "' is not an integer");
    }
    writeText(p, "1 2 3 0.5 1\n4 5 6 0.25 2.0\n");
    EXPECT_EQ(readSpheres(p, 2).size(), 1u); // 2.0 is the integer 2
    std::remove(p.c_str());
}

// The bug: an ASCII STL whose solid is named in UTF-8 was refused as "binary bytes".
TEST(MeshIo, test_utf8_solid_name_was_binary) {
    const std::string p = tempPath("utf8.stl");
    writeText(p, "solid Gr\xc3\xb6\xc3\x9f"
                 "e\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                 "vertex 0 1 0\nendloop\nendfacet\nendsolid Gr\xc3\xb6\xc3\x9f"
                 "e\n");
    EXPECT_EQ(readMesh(p).triangles.size(), 1u);
    writeText(p, std::string("solid x\n\x01\x02 binary", 17));
    expectError([&] { readMesh(p); }, "binary bytes");
    std::remove(p.c_str());
}

// The bug: an ASCII STL cut after a whole facet passed, with an "open mesh" warning.
TEST(MeshIo, test_truncated_ascii_stl_passed_as_open) {
    const std::string p = tempPath("cut.stl");
    const std::string facet =
        "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
        "endfacet\n";
    writeText(p, "solid t\n" + facet + facet);
    expectError([&] { readMesh(p); }, "ends without 'endsolid'");
    writeText(p, "solid t\n" + facet + "endsolid t\n");
    EXPECT_EQ(readMesh(p).triangles.size(), 1u);
    std::remove(p.c_str());
}

// The bug: a valid PLY that lists its faces before its vertices was refused (indices beyond the vertices
// read).
TEST(MeshIo, test_ply_faces_first_was_refused) {
    const std::string p = tempPath("faces_first.ply");
    writeText(p, "ply\nformat ascii 1.0\nelement face 4\nproperty list uchar int vertex_indices\n"
                 "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                 "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
    const TriangleMesh m = readMesh(p);
    EXPECT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.triangles.size(), 4u);
    writeText(p, "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                 "3 0 1 7\n0 0 0\n1 0 0\n0 1 0\n");
    expectError([&] { readMesh(p); }, "PLY face 0");
    std::remove(p.c_str());
}

TEST(SphereIo, ClumpTemplatesOfOtherCodesReadBackWhereGenerated) {
    // a LIGGGHTS template as mss export writes it: the spheres go back to c + R p
    const std::string lig = tempPath("t.in");
    writeText(lig,
              "# header\n#   c = 1 2 3\n#   R = 0 -1 0 ; 1 0 0 ; 0 0 1 (rows)\nfix t all "
              "particletemplate/multisphere 15485863 atom_type 1 density constant 1000 nspheres 2 ntry 1000 "
              "spheres &\n    0.5 0 0 1 &\n    -0.5 0 0 0.75 &\n    type 1 mass 1 use_density inertia_tensor "
              "1 0 0 1 0 1\n");
    SphereSet s = readSpheres(lig);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_NEAR((s.centers[0] - Vec3(1.0, 2.5, 3.0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((s.centers[1] - Vec3(1.0, 1.5, 3.0)).norm(), 0.0, 1e-15);
    EXPECT_EQ(s.radii[1], 0.75);
    // a Kratos cluster of another program (no c, R): relative to Particle_center_and_diameter's centre
    const std::string clu = tempPath("t.clu");
    writeText(clu, "//\nName\nx\n\nBegin centers_and_radii\n1 0 0 0.5\n// a comment\n-1 0 0 0.5\nEnd "
                   "centers_and_radii\n\nParticle_center_and_diameter\n0.5 0 0 3\n\nVolume\n1\n");
    s = readSpheres(clu);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_EQ(s.centers[0], Vec3(0.5, 0.0, 0.0));
    EXPECT_EQ(s.centers[1], Vec3(-1.5, 0.0, 0.0));
    // templates it cannot read: named, never guessed
    writeText(lig,
              "fix t all particletemplate/multisphere 1 nspheres 3 ntry 1 spheres 0 0 0 1 1 0 0 1 type 1\n");
    expectError([&] { readSpheres(lig); }, "fewer numbers follow spheres");
    writeText(lig,
              "fix t all particletemplate/multisphere 1 nspheres 3 ntry 1 spheres file pebbles.txt type 1\n");
    expectError([&] { readSpheres(lig); }, "in the file pebbles.txt");
    writeText(lig,
              "fix a all particletemplate/multisphere 1 nspheres 1 ntry 1 spheres 0 0 0 1 type 1\nfix b all "
              "particletemplate/multisphere 1 nspheres 1 ntry 1 spheres 0 0 0 1 type 2\n");
    expectError([&] { readSpheres(lig); }, "2 fix particletemplate/multisphere commands");
    writeText(lig, "fix t all particletemplate/multisphere 1 nspheres 1 ntry 1 spheres 0 nan 0 1 type 1\n");
    expectError([&] { readSpheres(lig); }, "not a finite number");
    writeText(lig,
              "#   R = 2 0 0 ; 0 1 0 ; 0 0 1 (rows)\n#   c = 0 0 0\nfix t all particletemplate/multisphere 1 "
              "nspheres 1 ntry 1 spheres 0 0 0 1 type 1\n");
    expectError([&] { readSpheres(lig); }, "not a rotation");
    writeText(clu, "Begin centers_and_radii\n1 0 0 0.5\n");
    expectError([&] { readSpheres(clu); }, "no End centers_and_radii");
    writeText(clu, "Begin centers_and_radii\n1 0 0\nEnd centers_and_radii\n");
    expectError([&] { readSpheres(clu); }, "must be x y z r");
    writeText(clu, "Begin centers_and_radii\n1 0 0 -1\nEnd centers_and_radii\n");
    expectError([&] { readSpheres(clu); }, "readSpheres");
    std::remove(lig.c_str());
    std::remove(clu.c_str());
}

TEST(SphereIo, PfcAndYadeTemplatesReadBack) {
    // PFC: continuation '...', ';' comments, a vector in parentheses; with the header, the pebbles about the
    // position go to c + R p
    const std::string pfc = tempPath("t.p3dat");
    writeText(
        pfc,
        ";   c = 1 2 3\n;   R = 0 -1 0 ; 1 0 0 ; 0 0 1 (rows)\nclump template create name 'x' ... ; here\n"
        "  pebbles 2 ...\n  1 10.5 0 0 ...\n  0.75 9.5 0 0 ...\n  volume 1 inertia 1 1 1 0 0 0 ...\n"
        "  position (10,0,0)\n");
    SphereSet s = readSpheres(pfc);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_NEAR((s.centers[0] - Vec3(1.0, 2.5, 3.0)).norm(), 0.0, 1e-15);
    EXPECT_NEAR((s.centers[1] - Vec3(1.0, 1.5, 3.0)).norm(), 0.0, 1e-15);
    EXPECT_EQ(s.radii[0], 1.0);
    // another program's template (no header): the pebbles as written, keywords in any case
    writeText(
        pfc,
        "CLUMP TEMPLATE CREATE NAME y PEBBLES 1 0.5 1 2 3 VOLUME 1 INERTIA 1 1 1 0 0 0 POSITION 1 2 3\n");
    s = readSpheres(pfc);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_EQ(s.centers[0], Vec3(1.0, 2.0, 3.0));
    writeText(pfc, "clump template create name y pebbles 3 0.5 1 2 3 volume 1\n");
    expectError([&] { readSpheres(pfc); }, "pebbles 3 but fewer numbers follow");
    writeText(pfc, "clump template create name y geometry g bubblepack distance 120 surfcalculate\n");
    expectError([&] { readSpheres(pfc); }, "no pebbles keyword");
    writeText(
        pfc,
        "clump template create name a pebbles 1 1 0 0 0\nclump template create name b pebbles 1 1 0 0 0\n");
    expectError([&] { readSpheres(pfc); }, "2 clump template create commands");
    writeText(pfc, "clump template create name y pebbles 1e300 1 0 0 0\n");
    expectError([&] { readSpheres(pfc); }, "pebbles must be an integer");
    writeText(pfc, "clump template create name y pebbles 1 -1 0 0 0\n");
    expectError([&] { readSpheres(pfc); }, "readSpheres");
    // the yade-mss clumps file of mss export: about the centre of mass, put back by the header
    const std::string txt = tempPath("t.txt");
    writeText(
        txt,
        "# written by mss export --format yade from g.stl\n#   c = 1 2 3\n#   R = 0 -1 0 ; 1 0 0 ; 0 0 1 "
        "(rows)\n#mss clump 0 density 1 mass 1 centroid 0 0 0 inertia 1 1 1 0 0 0\n0.5 0 0 1 0\n");
    s = readSpheres(txt);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_NEAR((s.centers[0] - Vec3(1.0, 2.5, 3.0)).norm(), 0.0, 1e-15);
    writeText(txt, "# written by mss export --format yade\n0.5 0 0 1\n");
    expectError([&] { readSpheres(txt); }, "must be x y z r clumpId");
    std::remove(pfc.c_str());
    std::remove(txt.c_str());
}

// The batch's tables (io/number_rows.cpp): numbers as Python's repr and printf's "%.17g" write them.
TEST(NumberText, ShortestIsPythonsReprAndPrecision17IsPrintfs) {
    const std::pair<double, const char*> shortest[] = {{0.0, "0.0"},
                                                       {-0.0, "-0.0"},
                                                       {0.1, "0.1"},
                                                       {100.0, "100.0"},
                                                       {1e15, "1000000000000000.0"},
                                                       {1e16, "1e+16"},
                                                       {1e-4, "0.0001"},
                                                       {1e-5, "1e-05"},
                                                       {-2.5, "-2.5"},
                                                       {1e22, "1e+22"},
                                                       {5e-324, "5e-324"},
                                                       {123456789012345678.0, "1.2345678901234568e+17"},
                                                       {1.7976931348623157e308, "1.7976931348623157e+308"},
                                                       {std::numeric_limits<double>::infinity(), "inf"},
                                                       {-std::numeric_limits<double>::infinity(), "-inf"},
                                                       {std::nan(""), "nan"}};
    for (const auto& [v, text] : shortest) {
        std::string out;
        mss::appendNumber(out, v, mss::NumberText::Shortest);
        EXPECT_EQ(out, text) << v;
    }
    for (double v : {0.1, 100.0, 1e-5, 123456789012345678.0, -0.0}) {
        char want[64];
        std::snprintf(want, sizeof want, "%.17g", v);
        std::string out;
        mss::appendNumber(out, v, mss::NumberText::Precision17);
        EXPECT_EQ(out, want);
    }
}

TEST(NumberText, RowsAndTheAssemblyRefuseWhatDoesNotAddUp) {
    const std::int64_t ints[] = {1, 2};
    const double values[] = {0.5, 2.0};
    EXPECT_EQ(mss::formatRows(ints, 1, values, 1, 2, mss::NumberText::Shortest, ',', "\r\n"),
              "1,0.5\r\n2,2.0\r\n");
    EXPECT_THROW(mss::formatRows(nullptr, 1, values, 1, 2, mss::NumberText::Shortest, ',', "\n"),
                 std::invalid_argument);
    const double spheres[8] = {0, 0, 0, 1, 1, 0, 0, 1};
    const double heads[20] = {};
    const std::int64_t ids[2] = {7, 8};
    const std::int64_t down[3] = {0, 2, 1};
    EXPECT_THROW(mss::formatClumpAssembly(spheres, 2, down, ids, heads, 2), std::invalid_argument);
    const std::int64_t past[3] = {0, 1, 3};
    EXPECT_THROW(mss::formatClumpAssembly(spheres, 2, past, ids, heads, 2), std::invalid_argument);
    const std::int64_t ok[3] = {0, 1, 2};
    const std::string text = mss::formatClumpAssembly(spheres, 2, ok, ids, heads, 2);
    EXPECT_EQ(text.substr(0, text.find('\n') + 1),
              "#mss clump 7 density 1 mass 0.0 centroid 0.0 0.0 0.0 inertia 0.0 0.0 0.0 0.0 0.0 0.0\n");
    EXPECT_NE(text.find("\n0.0 0.0 0.0 1.0 7\n#mss clump 8"), std::string::npos);
    EXPECT_EQ(text.substr(text.size() - 18), "1.0 0.0 0.0 1.0 8\n");
}
