// A DEM code's particle from a mesh: its spheres (members of a rigid clump) and the mass, centre of mass and
// principal moments of the grain itself, which the clump should carry (not the union of its spheres).
// usage: grain_to_spheres MESH N_SPHERES DENSITY [SCALE]
// SCALE multiplies the mesh's coordinates as read (1e-3: a mesh in millimetres, results in metres); DENSITY
// is per cubed unit of the scaled mesh (kg/m^3 in SI).
#include <mss.hpp>

#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

int main(int argc, char** argv) {
    if (argc != 4 && argc != 5) {
        std::fprintf(stderr, "usage: %s MESH N_SPHERES DENSITY [SCALE]\n", argv[0]);
        return 2;
    }
    try {
        mss::TriangleMesh mesh = mss::readMesh(argv[1]);
        double scale = 1.0;
        if (argc == 5) {
            std::size_t used = 0;
            try {
                scale = std::stod(argv[4], &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != std::string(argv[4]).size() || !(scale > 0) || !std::isfinite(scale))
                throw std::invalid_argument("SCALE must be a number > 0, got '" + std::string(argv[4]) + "'");
        }
        for (mss::Vec3& v : mesh.vertices) v *= scale;
        mss::GenerateOptions options;
        options.nSpheres = std::stoi(argv[2]);
        mss::Resolution resolution;
        resolution.resolution = 60;
        const mss::Result result = mss::generate(mesh, resolution, options);
        const double density = std::stod(argv[3]);
        const mss::MassProperties grain = mss::meshMassProperties(mesh);
        mss::Vec3 moments;
        Eigen::Matrix3d axes;
        grain.principal(moments, axes);
        std::printf("spheres %zu\ndice %.6g\n", result.spheres.size(), result.metrics.dice);
        std::printf("mass %.10g\ncentre %.10g %.10g %.10g\nmoments %.10g %.10g %.10g\n",
                    density * grain.volume, grain.centroid.x(), grain.centroid.y(), grain.centroid.z(),
                    density * moments.x(), density * moments.y(), density * moments.z());
        for (std::size_t i = 0; i < result.spheres.size(); ++i) {
            const mss::Vec3& c = result.spheres.centers[i];
            std::printf("sphere %.10g %.10g %.10g %.10g\n", c.x(), c.y(), c.z(), result.spheres.radii[i]);
        }
    } catch (const std::exception& e) { // bad files and options: std::invalid_argument with the reason
        std::fprintf(stderr, "grain_to_spheres: %s\n", e.what());
        return 1;
    }
    return 0;
}
