#include "terrain/terrain_images.h"

#include <mutex>

#include "splatkit/error.h"
#include "splatkit/load_module.h"
#include "splatkit/lower_extension.h"
#include "terrain/tiff_geo_tags.h"

namespace splatkit::terrain {

namespace {

// Loads the module, or returns why not.
const TerrainImages* load(std::string& why) {
  std::string path;
  void* symbol = load_module(SPLATKIT_TERRAIN_MODULE_NAME, SPLATKIT_TERRAIN_MODULE_BUILD_PATH,
                             kTerrainImagesEntry, why, path);
  if (symbol == nullptr) return nullptr;
  using Entry = const TerrainImages* (*)();
  const TerrainImages* images = reinterpret_cast<Entry>(symbol)();
  if (images == nullptr || images->version != kTerrainImagesVersion) {
    why = path + " is not this build's module";
    return nullptr;
  }
  return images;
}

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
  static std::string why;
  static const TerrainImages* images = nullptr;
  static std::once_flag once;
  std::call_once(once, [] { images = load(why); });
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
