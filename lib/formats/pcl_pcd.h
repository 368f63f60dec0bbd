// PCL's PCD reader, loaded on first use: it lives in a module of its own (splatkit_pcl_pcd, a
// shared object opened with dlopen) because linking PCL's io loads about 60 shared libraries (VTK,
// Boost, libtiff, ...) into every tool at start-up, some 17 ms per run, which only a run that
// reads a .pcd file needs. As for the OpenImageIO module (render/oiio_images.h): looked for in
// <directory of the executable>/../lib/splatkit/, then where the build tree put it; the interface
// is C++ between two sides built from the same sources; nothing throws across it (std::bad_alloc
// aside).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "splatkit/scalar_type.h"

namespace splatkit {

inline constexpr int kPclPcdVersion = 1;

// One field of PCL's point record.
struct PclField {
  std::string name;
  uint32_t offset = 0, count = 0;
  std::optional<ScalarType> type;  // none for a type splatkit does not read (PCL's bool)
};

// What PCL read: `width * height` records of `point_step` bytes in `data`.
struct PclRecords {
  std::vector<PclField> fields;
  uint32_t width = 0, height = 0, point_step = 0;
  std::vector<uint8_t> data;
};

struct PclPcd {
  int version = kPclPcdVersion;
  // Reads the PCD file at `path` with pcl::PCDReader into `out`. Returns "" on success, else
  // why not, to follow "<file>: ".
  std::string (*read)(const std::string& path, PclRecords& out) = nullptr;
};

// The module's entry point, exported with C linkage under this name.
inline constexpr const char* kPclPcdEntry = "splatkit_pcl_pcd";

// The loaded module (loaded once per process, kept). Throws Error(kUnsupported) naming `path`
// (the file that needs it) when no module can be loaded or its version differs.
const PclPcd& pcl_pcd(const std::string& path);

}  // namespace splatkit
