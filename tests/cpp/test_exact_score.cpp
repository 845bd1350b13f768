// Scores on the exact shapes by Monte Carlo (mss compare --exact): closed forms within a few standard errors,
// the same figures for any thread count, and the lattice bias of the grid score that it does not have.
#include "mss/compare.hpp"
#include "mss/io.hpp"
#include "mss/mass.hpp"
#include "mss/score.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <omp.h>
#include <stdexcept>
#include <string>

using namespace mss;

namespace {
const std::string kData = MSS_TEST_DATA;
constexpr double kPi = 3.14159265358979323846;

/// The unit cube against the ball of diameter 1 at its centre: |A| = 1, |B| = pi / 6, B inside A.
double cubeBallDice() {
    return (1.0 - kPi / 6.0) / (1.0 + kPi / 6.0);
}
} // namespace

TEST(ExactScore, CubeAndInscribedBallWithinFourStandardErrors) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl");
    SphereSet ball;
    ball.add(Vec3(0, 0, 0), 0.5);
    const ExactScore e = scoreSpheresExact(cube, ball, 400000, 3);
    EXPECT_NEAR(e.dice, cubeBallDice(), 4 * e.diceError);
    EXPECT_NEAR(e.eta, 1.0 - kPi / 6.0, 4 * e.etaError);
    EXPECT_NEAR(e.targetVolume, 1.0, 4 * e.targetVolumeError);
    EXPECT_NEAR(e.sphereVolume, kPi / 6.0, 4 * e.sphereVolumeError);
    EXPECT_GT(e.diceError, 0.0);
    EXPECT_LT(e.diceError, 0.002);
    // a quarter of the points: about twice the error
    const ExactScore q = scoreSpheresExact(cube, ball, 100000, 3);
    EXPECT_NEAR(q.diceError / e.diceError, 2.0, 0.1);
}

TEST(ExactScore, VoxelTargetIsTheUnionOfItsCubes) {
    VoxelGrid v(GridSpec{{3, 3, 3}, 0.5, Vec3(-0.5, -0.5, -0.5)}, 1); // the cube [-0.75, 0.75]^3
    SphereSet ball;
    ball.add(Vec3(0, 0, 0), 0.75);
    const ExactScore e = scoreSpheresExact(v, ball, 400000, 5);
    EXPECT_NEAR(e.targetVolume, 1.5 * 1.5 * 1.5, 4 * e.targetVolumeError);
    EXPECT_NEAR(e.dice, cubeBallDice(), 4 * e.diceError);
    // with a plane: the half x >= 0 (voxel centres at 0 kept)
    const ExactScore h = scoreSpheresExact(v, ball, 400000, 5, {Plane{Vec3(0, 0, 0), Vec3(1, 0, 0)}});
    EXPECT_LT(h.targetVolume, e.targetVolume);
}

TEST(ExactScore, TheSameForAnyThreadCountAndSeedDependent) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl");
    SphereSet s;
    s.add(Vec3(0.1, 0, 0), 0.45);
    s.add(Vec3(-0.2, 0.1, 0), 0.4);
    const int before = omp_get_max_threads();
    omp_set_num_threads(1);
    const ExactScore one = scoreSpheresExact(cube, s, 50000, 9);
    omp_set_num_threads(2);
    const ExactScore two = scoreSpheresExact(cube, s, 50000, 9);
    omp_set_num_threads(before);
    EXPECT_EQ(one.dice, two.dice);
    EXPECT_EQ(one.targetVolume, two.targetVolume);
    const ExactScore other = scoreSpheresExact(cube, s, 50000, 10);
    EXPECT_NE(other.dice, one.dice);
    EXPECT_NEAR(other.dice, one.dice, 5 * std::hypot(one.diceError, other.diceError));
}

TEST(ExactScore, BadSamplesAreRefused) {
    const TriangleMesh cube = readMesh(kData + "/cube.stl");
    SphereSet s;
    s.add(Vec3(0, 0, 0), 0.5);
    EXPECT_THROW(scoreSpheresExact(cube, s, 10), std::invalid_argument);
    // compare --exact fills the row's exact score; without it, samples stay 0
    CompareOptions o;
    EXPECT_EQ(compareSpheres(cube, s, o).exact.samples, 0u);
    o.exact = true;
    o.samples = 20000;
    const Comparison c = compareSpheres(cube, s, o);
    EXPECT_EQ(c.exact.samples, 20000u);
    EXPECT_NEAR(c.exact.dice, cubeBallDice(), 5 * c.exact.diceError);
}

TEST(ExactScore, ClosedMeshesLookedUpByCellsKeepTheirVolume) {
    // the cells that no surface reaches are answered by lookup: a wrong group of them would move the volume
    // by far more than its standard error (the torus: its hole a group outside, enclosed by the ring)
    for (const char* name : {"/torus.stl", "/human_femur.stl", "/octahedron.stl"}) {
        const TriangleMesh m = readMesh(kData + name);
        SphereSet s;
        const MeshInfo info = analyzeMesh(m);
        s.add(0.5 * (info.lower + info.upper), 0.01 * (info.upper - info.lower).norm());
        const ExactScore e = scoreSpheresExact(m, s, 300000, 11);
        EXPECT_NEAR(e.targetVolume, meshMassProperties(m).volume, 4 * e.targetVolumeError) << name;
    }
}
