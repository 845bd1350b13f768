#include "mss/mass.hpp"
#include "mss/voxelize.hpp"

#include <Eigen/Eigenvalues>

#include <stdexcept>

namespace mss {

void MassProperties::principal(Vec3& moments, Eigen::Matrix3d& axes) const {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(inertia);
    moments = es.eigenvalues();
    axes = es.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) = -axes.col(2); // a rotation, not a reflection
}

namespace {

/// Inertia tensor about the centroid from integrals of 1, x, y, z, x^2, y^2, z^2, xy, yz, zx (about an
/// origin).
MassProperties fromIntegrals(const double in[10], const Vec3& origin) {
    MassProperties m;
    m.volume = in[0];
    const Vec3 c(in[1] / in[0], in[2] / in[0], in[3] / in[0]);
    const double V = in[0];
    Eigen::Matrix3d I;
    I(0, 0) = in[5] + in[6] - V * (c.y() * c.y() + c.z() * c.z());
    I(1, 1) = in[4] + in[6] - V * (c.z() * c.z() + c.x() * c.x());
    I(2, 2) = in[4] + in[5] - V * (c.x() * c.x() + c.y() * c.y());
    I(0, 1) = I(1, 0) = -(in[7] - V * c.x() * c.y());
    I(1, 2) = I(2, 1) = -(in[8] - V * c.y() * c.z());
    I(0, 2) = I(2, 0) = -(in[9] - V * c.z() * c.x());
    m.centroid = origin + c;
    m.inertia = I;
    return m;
}

inline void subexpressions(double w0, double w1, double w2, double& f1, double& f2, double& f3, double& g0,
                           double& g1, double& g2) {
    const double t0 = w0 + w1, t1 = w0 * w0, t2 = t1 + w1 * t0;
    f1 = t0 + w2;
    f2 = t2 + w2 * f1;
    f3 = w0 * t1 + w1 * t2 + w2 * f2;
    g0 = f2 + w0 * (f1 + w0);
    g1 = f2 + w1 * (f1 + w1);
    g2 = f2 + w2 * (f1 + w2);
}

} // namespace

MassProperties meshMassProperties(const TriangleMesh& mesh) {
    validateMesh(mesh, "meshMassProperties");
    // integrate about the box centre: less cancellation (meshBox: analyzeMesh also walks every edge, which
    // was most of this function's time)
    const auto [lower, upper] = meshBox(mesh);
    const Vec3 o = 0.5 * (lower + upper);
    double in[10] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (const auto& t : mesh.triangles) {
        const Vec3 p0 = mesh.vertices[t[0]] - o, p1 = mesh.vertices[t[1]] - o, p2 = mesh.vertices[t[2]] - o;
        const Vec3 d = (p1 - p0).cross(p2 - p0);
        double f1x, f2x, f3x, g0x, g1x, g2x, f1y, f2y, f3y, g0y, g1y, g2y, f1z, f2z, f3z, g0z, g1z, g2z;
        subexpressions(p0.x(), p1.x(), p2.x(), f1x, f2x, f3x, g0x, g1x, g2x);
        subexpressions(p0.y(), p1.y(), p2.y(), f1y, f2y, f3y, g0y, g1y, g2y);
        subexpressions(p0.z(), p1.z(), p2.z(), f1z, f2z, f3z, g0z, g1z, g2z);
        in[0] += d.x() * f1x;
        in[1] += d.x() * f2x;
        in[2] += d.y() * f2y;
        in[3] += d.z() * f2z;
        in[4] += d.x() * f3x;
        in[5] += d.y() * f3y;
        in[6] += d.z() * f3z;
        in[7] += d.x() * (p0.y() * g0x + p1.y() * g1x + p2.y() * g2x);
        in[8] += d.y() * (p0.z() * g0y + p1.z() * g1y + p2.z() * g2y);
        in[9] += d.z() * (p0.x() * g0z + p1.x() * g1z + p2.x() * g2z);
    }
    const double mult[10] = {1. / 6,  1. / 24, 1. / 24,  1. / 24,  1. / 60,
                             1. / 60, 1. / 60, 1. / 120, 1. / 120, 1. / 120};
    const double sign = in[0] < 0 ? -1.0 : 1.0; // inside-out mesh: every integral flips sign
    for (int q = 0; q < 10; ++q) in[q] *= mult[q] * sign;
    if (!(in[0] > 0.0)) throw std::invalid_argument("meshMassProperties: the mesh encloses no volume");
    return fromIntegrals(in, o);
}

MassProperties voxelMassProperties(const VoxelGrid& v) {
    const GridSpec& g = v.spec;
    const Vec3 o = g.toWorld(Vec3(0.5 * (g.dims[0] - 1), 0.5 * (g.dims[1] - 1), 0.5 * (g.dims[2] - 1)));
    const double h = g.h, dv = h * h * h;
    double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, syy = 0, szz = 0, sxy = 0, syz = 0, szx = 0;
    for (int k = 0; k < v.nz(); ++k)
        for (int j = 0; j < v.ny(); ++j)
            for (int i = 0; i < v.nx(); ++i) {
                if (!v(i, j, k)) continue;
                const Vec3 p = g.voxelCenter(i, j, k) - o;
                n += 1;
                sx += p.x(), sy += p.y(), sz += p.z();
                sxx += p.x() * p.x(), syy += p.y() * p.y(), szz += p.z() * p.z();
                sxy += p.x() * p.y(), syz += p.y() * p.z(), szx += p.z() * p.x();
            }
    if (n == 0) throw std::invalid_argument("voxelMassProperties: the volume has no solid voxel");
    // a cube of edge h: integral of x^2 over it = dv * (x_c^2 + h^2 / 12)
    const double own = n * dv * h * h / 12.0;
    const double in[10] = {n * dv,         sx * dv,        sy * dv,  sz * dv,  sxx * dv + own,
                           syy * dv + own, szz * dv + own, sxy * dv, syz * dv, szx * dv};
    return fromIntegrals(in, o);
}

MassProperties sphereUnionMassProperties(const SphereSet& spheres, int resolution) {
    validateSpheres(spheres, "sphereUnionMassProperties");
    if (spheres.size() == 0) throw std::invalid_argument("sphereUnionMassProperties: no spheres");
    if (resolution < 1) throw std::invalid_argument("sphereUnionMassProperties: resolution must be >= 1");
    Vec3 lo = spheres.centers[0], hi = lo;
    for (std::size_t i = 0; i < spheres.size(); ++i) {
        lo = lo.cwiseMin(spheres.centers[i] - Vec3::Constant(spheres.radii[i]));
        hi = hi.cwiseMax(spheres.centers[i] + Vec3::Constant(spheres.radii[i]));
    }
    Resolution res;
    res.resolution = resolution;
    res.padding = 1;
    return voxelMassProperties(
        voxelizeSpheres(spheres, gridForBox(lo, hi, res, "sphereUnionMassProperties")));
}

} // namespace mss
