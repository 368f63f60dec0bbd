// OpenImageIO for terrain, loaded on first use like render/oiio_images.h (same reasons, same
// places looked in): reads TIFF (8/16/32-bit integer and float, stripped or tiled), PNG (8 and 16
// bit), EXR and every other format OpenImageIO reads as heightmaps, writes and reads the per-tile
// HAM EXR (ham_tiles.h) and writes the full-resolution HAM as a tiled float EXR, row by row.
// Nothing throws across the module: its functions return "" or OpenImageIO's message.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "terrain/ham_tiles.h"
#include "terrain/heightmap_source.h"

namespace splatkit::terrain {

inline constexpr int kTerrainImagesVersion = 1;

// Rows of a raster image, top first, channel 0 converted to float without normalisation.
class RasterRows {
 public:
  virtual ~RasterRows() = default;
  HeightmapInfo info;
  virtual std::string read(int64_t rows, float* out) = 0;
};

// Takes HAM rows in order and writes them as EXR tiles; close() finishes the file.
class RowWriter {
 public:
  virtual ~RowWriter() = default;
  virtual std::string write(int64_t rows, const float* data) = 0;
  virtual std::string close() = 0;
};

struct TerrainImages {
  int version = kTerrainImagesVersion;
  std::string (*open_raster)(const std::string& path, std::unique_ptr<RasterRows>& out) = nullptr;
  std::string (*encode_tiles)(const HamTiles& tiles, std::vector<unsigned char>& bytes) = nullptr;
  std::string (*decode_tiles)(const std::string& path, HamTiles& tiles) = nullptr;
  std::string (*open_row_writer)(const std::string& path, int64_t width, int64_t height, int tile,
                                 const nlohmann::json& header,
                                 std::unique_ptr<RowWriter>& out) = nullptr;
};

inline constexpr const char* kTerrainImagesEntry = "splatkit_terrain_images";
// How read_ham_tiles' message begins for an EXR without the tiles' header (an ordinary image,
// which splat-info then describes as a heightmap).
inline constexpr const char* kNotHamTiles = "not a build-ham tile file";

// The loaded module. Throws Error(kUnsupported) naming `path` when it cannot be loaded.
const TerrainImages& terrain_images(const std::string& path);

// A heightmap through the module; the TIFF's own no-data and georeferencing tags are read
// beside it (tiff_geo_tags.h). Throws Error(kBadInput) / Error(kUnsupported) naming the file.
std::unique_ptr<HeightmapSource> open_image_heightmap(const std::string& path);

// The per-tile HAM EXR. Throws Error(kBadInput) naming the file when a channel or header
// attribute is missing or inconsistent.
HamTiles read_ham_tiles(const std::string& path);

}  // namespace splatkit::terrain
