#pragma once
/// What program wrote an output: its version and the commit it was built
/// from. Defined in a file generated at every build (cmake/BuildInfo.cmake).
#include <string_view>

namespace conserve::build_info {

/// The program's version, CMake's project VERSION, e.g. "0.1.0".
std::string_view version();

/// The git commit of the source tree when it was built (40 hex digits),
/// with "-dirty" if tracked files were modified; "unknown" when it was not
/// built from a git checkout.
std::string_view commit();

}  // namespace conserve::build_info
