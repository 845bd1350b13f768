// The version of yade-mss: one place, the CMake project's (CMakeLists.txt), which the library, `mss
// --version`, yade_mss.__version__, the CMake and pkg-config files, the manual and CITATION.cff all give.
#pragma once

namespace mss {

/// This library's version, "MAJOR.MINOR.PATCH" (the CMake project's).
const char* version();

} // namespace mss
