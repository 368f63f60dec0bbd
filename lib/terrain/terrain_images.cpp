#include "terrain/terrain_images.h"

#include "splatkit/error.h"
#include "splatkit/load_module.h"
#include "splatkit/lower_extension.h"
#include "terrain/tiff_geo_tags.h"

namespace splatkit::terrain {

namespace {

class ImageSource final : public HeightmapSource {
 public:
  ImageSource(std::string path, std::unique_ptr<RasterRows> rows)
      : path_(std::move(path)), rows_(std::move(rows)) {
    info_ = rows_->info;
  }
  void read_rows(int64_t rows, float* out) override {
    const std::string why = rows_->read(rows, out);
    if (!why.empty()) throw_bad_input(display_name(path_), why);
  }

 private:
  std::string path_;
  std::unique_ptr<RasterRows> rows_;
};

}  // namespace

const TerrainImages& terrain_images(const std::string& path) {
  std::string why;
  const TerrainImages* images =
      loaded_module<TerrainImages>(SPLATKIT_TERRAIN_MODULE_NAME, SPLATKIT_TERRAIN_MODULE_BUILD_PATH,
                                   kTerrainImagesEntry, kTerrainImagesVersion, why);
  if (images == nullptr)
    throw_unsupported(display_name(path),
                      "heightmap images need splatkit's OpenImageIO terrain module: " + why);
  return *images;
}

std::unique_ptr<HeightmapSource> open_image_heightmap(const std::string& path) {
  if (path == "-")
    throw_usage("a TIFF, PNG or EXR heightmap cannot come from standard input (only --raw can)");
  std::unique_ptr<RasterRows> rows;
  const std::string why = terrain_images(path).open_raster(path, rows);
  if (!why.empty()) throw_bad_input(display_name(path), why);
  if (rows->info.format == "tiff") {
    const TiffGeoTags tags = read_tiff_geo_tags_file(path);
    if (tags.nodata) {
      rows->info.has_nodata = true;
      rows->info.nodata = *tags.nodata;
    }
    rows->info.georef = tags.georef;
  }
  return std::make_unique<ImageSource>(path, std::move(rows));
}

HamTiles read_ham_tiles(const std::string& path) {
  HamTiles tiles;
  const std::string why = terrain_images(path).decode_tiles(path, tiles);
  if (!why.empty()) throw_bad_input(display_name(path), why);
  return tiles;
}

}  // namespace splatkit::terrain
