// Sphere sets: the output of MSS and the input of scoring, with their file formats.
#pragma once

#include "mss/grid.hpp"

#include <string>
#include <vector>

namespace mss {

/// A set of spheres in world units; centres[i] and radii[i] describe sphere i.
struct SphereSet {
    std::vector<Vec3> centers;
    std::vector<double> radii;

    std::size_t size() const { return radii.size(); }
    void add(const Vec3& c, double r) {
        centers.push_back(c);
        radii.push_back(r);
    }
};

/// Checks sizes agree, coordinates are finite and radii positive; throws std::invalid_argument naming @p
/// where.
void validateSpheres(const SphereSet& s, const std::string& where);

/// Writes spheres by extension: .csv ("x,y,z,r" header and rows), .txt (YADE text clump "x y z r clumpId",
/// the format of ymport.textClumps), .vtk (legacy VTK polydata, points with a "radius" scalar, for ParaView's
/// glyphs). Full precision (17 significant digits). Written to a temporary file and renamed, so an
/// interrupted run never leaves a half-written file. @throws std::invalid_argument on an unknown extension or
/// unwritable path.
void writeSpheres(const SphereSet& s, const std::string& path);

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

} // namespace mss
