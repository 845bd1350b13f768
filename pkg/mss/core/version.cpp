#include "mss/version.hpp"

#ifndef MSS_VERSION
#error "MSS_VERSION is set by CMakeLists.txt (the project's version)"
#endif

namespace mss {

const char* version() {
    return MSS_VERSION;
}

} // namespace mss
