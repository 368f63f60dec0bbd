// PCL's PCD (ascii, binary, binary_compressed), read through PCL's own reader. Spec:
// formats/pcd.md.
#pragma once

#include "formats/loaded_cloud.h"
#include "formats/read_cloud.h"

namespace splatkit {

// The header is validated here first (sizes, counts against the bytes present) because PCL's
// reader trusts it; fields x y z, normal_x.., rgb/rgba, curvature and others map as in pcd.md.
LoadedCloud read_pcd(InputStream& in, const ReadOptions& options = {});

}  // namespace splatkit
