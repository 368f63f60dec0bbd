// The extension of a path's last component, lower-cased, without the dot ("" when there is none):
// "scans/Part.PLY" -> "ply", "a.b/c" -> "", "x.tar.gz" -> "gz".
#pragma once

#include <string>

namespace splatkit {

std::string lower_extension(const std::string& path);

}  // namespace splatkit
