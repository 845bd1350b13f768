// Internal to the readers: sphere sets from other DEM codes' clump templates (io/template_spheres.cpp).
#pragma once

#include "mss/spheres.hpp"

#include <string>

namespace mss::detail {

/// The spheres of a clump template at @p path into @p out, true where it is one: a LIGGGHTS include file
/// (fix particletemplate/multisphere with its spheres inline), a Kratos cluster (.clu, Begin
/// centers_and_radii) or a MercuryDPM clump folder (Clump/Clump.txt). Where the header says where the grain
/// was generated (mss export writes c and R), the spheres go back there. False: none of these (the caller
/// reads plain text).
/// @throws std::invalid_argument naming the file and the problem (a template it cannot read).
bool readTemplateSpheres(const std::string& path, SphereSet& out);

} // namespace mss::detail
