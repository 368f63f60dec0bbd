// The viewer page's files (web/), embedded in the binary at build time by embed_files.cmake, so
// that splat-view --serve needs nothing installed beside it and fetches nothing from elsewhere.
#pragma once

#include <cstddef>

namespace splatkit::serve {

struct ViewerAsset {
  const char* path;  // relative to web/, e.g. "index.html", "viewer.js"
  const unsigned char* data;
  std::size_t size;
};

extern const ViewerAsset kViewerAssets[];
extern const std::size_t kViewerAssetCount;

}  // namespace splatkit::serve
