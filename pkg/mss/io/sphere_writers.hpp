// The sphere writers, one file each; io/formats.cpp lists them. Each gives the whole text of the file, at
// full precision (17 significant digits); writeSpheres writes it atomically.
#pragma once

#include "mss/spheres.hpp"

#include <string>

namespace mss::detail {

/// .csv: an "x,y,z,r" header and a row per sphere (csv_spheres.cpp).
std::string formatCsv(const SphereSet& s);
/// .txt: YADE's text clump, "x y z r clumpId", what ymport.textClumps reads (yade_text_spheres.cpp).
std::string formatYadeText(const SphereSet& s);
/// .vtk: legacy VTK polydata, points with a "radius" scalar, for ParaView's glyphs (vtk_spheres.cpp).
std::string formatVtk(const SphereSet& s);

} // namespace mss::detail
