// splatkit_terrain_images: the module that reads heightmaps and writes the HAM EXR files through
// OpenImageIO (terrain_images.h).
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <memory>

#include "terrain/terrain_images.h"

namespace splatkit::terrain {

namespace {

using OIIO::TypeDesc;

// OpenImageIO's messages may span lines; splatkit's errors are one line.
std::string one_line(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  for (std::size_t i = s.find('\n'); i != std::string::npos; i = s.find('\n', i)) s.replace(i, 1, "; ");
  return s;
}

std::string sample_type_name(TypeDesc t) {
  switch (t.basetype) {
    case TypeDesc::UINT8: return "uint8";
    case TypeDesc::INT8: return "int8";
    case TypeDesc::UINT16: return "uint16";
    case TypeDesc::INT16: return "int16";
    case TypeDesc::UINT32: return "uint32";
    case TypeDesc::INT32: return "int32";
    case TypeDesc::HALF: return "float16";
    case TypeDesc::FLOAT: return "float32";
    case TypeDesc::DOUBLE: return "float64";
    default: return "";
  }
}

class OiioRows final : public RasterRows {
 public:
  std::unique_ptr<OIIO::ImageInput> in;
  TypeDesc type;
  int64_t next = 0;
  bool tiled = false;
  std::vector<unsigned char> buf;

  std::string read(int64_t rows, float* out) override {
    const int64_t w = info.width;
    const int y0 = int(next), y1 = int(next + rows);
    const bool as_float = type.basetype == TypeDesc::HALF || type.basetype == TypeDesc::FLOAT;
    // Tiled files are read a row of tiles at a time (rows is a multiple of the tile height).
    auto get = [&](TypeDesc t, void* data) {
      return tiled ? in->read_tiles(0, 0, 0, int(w), y0, y1, 0, 1, 0, 1, t, data)
                   : in->read_scanlines(0, 0, y0, y1, 0, 0, 1, t, data);
    };
    if (as_float) {
      if (!get(TypeDesc::FLOAT, out)) return error();
    } else {
      buf.resize(std::size_t(rows * w) * type.size());
      if (!get(type, buf.data())) return error();
      const std::size_t n = std::size_t(rows * w);
      convert(n, out);
    }
    next += rows;
    return "";
  }

 private:
  std::string error() {
    std::string e = one_line(in->geterror());
    return e.empty() ? "OpenImageIO could not read rows" : e;
  }
  template <class T>
  void convert_as(std::size_t n, float* out) {
    const T* p = reinterpret_cast<const T*>(buf.data());
    for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<float>(p[i]);
  }
  void convert(std::size_t n, float* out) {
    switch (type.basetype) {
      case TypeDesc::UINT8: convert_as<uint8_t>(n, out); break;
      case TypeDesc::INT8: convert_as<int8_t>(n, out); break;
      case TypeDesc::UINT16: convert_as<uint16_t>(n, out); break;
      case TypeDesc::INT16: convert_as<int16_t>(n, out); break;
      case TypeDesc::UINT32: convert_as<uint32_t>(n, out); break;
      case TypeDesc::INT32: convert_as<int32_t>(n, out); break;
      default: convert_as<double>(n, out); break;
    }
  }
};

std::string open_raster(const std::string& path, std::unique_ptr<RasterRows>& out) {
  // Rows are streamed: OpenImageIO's cap on whole-image sizes does not apply.
  OIIO::attribute("limits:imagesize_MB", 0);
  auto rows = std::make_unique<OiioRows>();
  rows->in = OIIO::ImageInput::open(path);
  if (!rows->in) {
    std::string e = one_line(OIIO::geterror());
    return e.empty() ? "OpenImageIO cannot read this file" : e;
  }
  const OIIO::ImageSpec& spec = rows->in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1)
    return "not a 2-D image (" + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
           ")";
  rows->type = spec.channelformat(0);
  rows->info.sample_type = sample_type_name(rows->type);
  if (rows->info.sample_type.empty())
    return "unsupported sample type " + std::string(rows->type.c_str());
  rows->info.width = spec.width;
  rows->info.height = spec.height;
  rows->info.format = rows->in->format_name();
  // An uncompressed file must hold every sample: a header claiming more is refused before any
  // memory is set aside for its rows.
  const std::string compression = spec.get_string_attribute("compression", "none");
  const uint64_t file_size = OIIO::Filesystem::file_size(path);
  const uint64_t need = uint64_t(spec.width) * uint64_t(spec.height) * rows->type.size();
  if (std::string(rows->in->format_name()) == "tiff" && compression == "none" && file_size < need)
    return "truncated: " + std::to_string(file_size) + " bytes cannot hold " +
           std::to_string(spec.width) + " x " + std::to_string(spec.height) + " uncompressed " +
           rows->info.sample_type + " samples";
  rows->tiled = spec.tile_width > 0 && spec.tile_height > 0;
  rows->info.band_rows = rows->tiled ? (64 + spec.tile_height - 1) / spec.tile_height * spec.tile_height : 64;
  out = std::move(rows);
  return "";
}

constexpr const char* kTileChannels[] = {"ham_max", "h_max", "x", "y", "voids"};

std::string encode_tiles(const HamTiles& t, std::vector<unsigned char>& bytes) {
  auto out = OIIO::ImageOutput::create("x.exr");
  if (!out) return "OpenImageIO cannot write EXR";
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  OIIO::ImageSpec spec(int(t.tiles_x), int(t.tiles_y), 5, TypeDesc::FLOAT);
  spec.channelnames.assign(std::begin(kTileChannels), std::end(kTileChannels));
  spec.channelformats = {TypeDesc::FLOAT, TypeDesc::FLOAT, TypeDesc::UINT32, TypeDesc::UINT32,
                         TypeDesc::UINT32};
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");
  spec.attribute("splatkit:tile_size", int(t.tile));
  spec.attribute("splatkit:width", int(t.width));
  spec.attribute("splatkit:height", int(t.height));
  spec.attribute("splatkit:z_scale", float(t.z_scale));
  spec.attribute("splatkit:ham", t.header.dump());
  if (!out->set_ioproxy(&proxy) || !out->open("tiles.exr", spec)) return out->geterror();
  std::vector<uint32_t> px(t.size() * 5);
  for (std::size_t i = 0; i < t.size(); ++i) {
    uint32_t* o = px.data() + 5 * i;
    std::memcpy(o + 0, &t.ham_max[i], 4);
    std::memcpy(o + 1, &t.h_max[i], 4);
    o[2] = t.x[i];
    o[3] = t.y[i];
    o[4] = t.voids[i];
  }
  if (!out->write_image(TypeDesc::UNKNOWN, px.data()) || !out->close()) {
    std::string e = out->geterror();
    return e.empty() ? "OpenImageIO failed to write the tiles" : e;
  }
  return "";
}

std::string decode_tiles(const std::string& path, HamTiles& t) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string e = one_line(OIIO::geterror());
    return e.empty() ? "OpenImageIO cannot read this file" : e;
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int tile = spec.get_int_attribute("splatkit:tile_size", 0);
  const int w = spec.get_int_attribute("splatkit:width", 0);
  const int h = spec.get_int_attribute("splatkit:height", 0);
  if (tile < 1 || w < 1 || h < 1)
    return std::string(kNotHamTiles) + " (splatkit:tile_size, width or height missing)";
  t.resize(w, h, tile);
  if (spec.width != t.tiles_x || spec.height != t.tiles_y)
    return "holds " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
           " tiles; a " + std::to_string(w) + " x " + std::to_string(h) + " map in tiles of " +
           std::to_string(tile) + " needs " + std::to_string(t.tiles_x) + " x " +
           std::to_string(t.tiles_y);
  t.z_scale = spec.get_float_attribute("splatkit:z_scale", 1.0f);
  t.header = nlohmann::json::parse(spec.get_string_attribute("splatkit:ham", "{}"), nullptr,
                                   false);
  if (t.header.is_discarded() || !t.header.is_object()) return "splatkit:ham is not JSON";
  const std::size_t n = t.size();
  for (int c = 0; c < 5; ++c) {
    const int index = spec.channelindex(kTileChannels[c]);
    if (index < 0) return std::string("has no channel ") + kTileChannels[c];
    const TypeDesc want = c < 2 ? TypeDesc::FLOAT : TypeDesc::UINT32;
    if (spec.channelformat(index) != want)
      return std::string("channel ") + kTileChannels[c] + " is not " + want.c_str();
    std::vector<uint32_t> plane(n);
    if (!in->read_image(0, 0, index, index + 1, want, plane.data())) return one_line(in->geterror());
    if (c == 0) std::memcpy(t.ham_max.data(), plane.data(), 4 * n);
    if (c == 1) std::memcpy(t.h_max.data(), plane.data(), 4 * n);
    if (c == 2) t.x = plane;
    if (c == 3) t.y = plane;
    if (c == 4) t.voids = plane;
  }
  for (std::size_t i = 0; i < n; ++i)
    if (t.x[i] >= uint64_t(w) || t.y[i] >= uint64_t(h) || !std::isfinite(t.h_max[i]) ||
        !std::isfinite(t.ham_max[i]) || t.ham_max[i] < 0)
      return "tile " + std::to_string(i) + " holds a texel outside the map or a non-finite value";
  return "";
}

class TiledRowWriter final : public RowWriter {
 public:
  std::unique_ptr<OIIO::ImageOutput> out;
  int64_t width = 0, height = 0, tile = 64, next = 0, buffered = 0;
  std::vector<float> buf;

  std::string write(int64_t rows, const float* data) override {
    while (rows > 0) {
      const int64_t take = std::min(rows, tile - buffered);
      std::memcpy(buf.data() + buffered * width, data, std::size_t(take * width) * 4);
      buffered += take;
      rows -= take;
      data += take * width;
      if (buffered == tile || next + buffered == height) {
        if (!out->write_tiles(0, int(width), int(next), int(next + buffered), 0, 1,
                              TypeDesc::FLOAT, buf.data()))
          return out->geterror();
        next += buffered;
        buffered = 0;
      }
    }
    return "";
  }
  std::string close() override {
    if (!out->close()) return out->geterror();
    return "";
  }
};

std::string open_row_writer(const std::string& path, int64_t width, int64_t height, int tile,
                            const nlohmann::json& header, std::unique_ptr<RowWriter>& result) {
  auto w = std::make_unique<TiledRowWriter>();
  w->out = OIIO::ImageOutput::create("x.exr");
  if (!w->out) return "OpenImageIO cannot write EXR";
  OIIO::ImageSpec spec(int(width), int(height), 1, TypeDesc::FLOAT);
  spec.channelnames = {"ham"};
  spec.tile_width = spec.tile_height = tile;
  spec.attribute("compression", "zip");
  spec.attribute("DateTime", "");
  spec.attribute("splatkit:ham", header.dump());
  if (!w->out->open(path, spec)) return w->out->geterror();
  w->width = width;
  w->height = height;
  w->tile = tile;
  w->buf.resize(std::size_t(width * tile));
  result = std::move(w);
  return "";
}

const TerrainImages kImages{kTerrainImagesVersion, open_raster, encode_tiles, decode_tiles,
                            open_row_writer};

}  // namespace

}  // namespace splatkit::terrain

extern "C" __attribute__((visibility("default"))) const splatkit::terrain::TerrainImages*
splatkit_terrain_images() {
  return &splatkit::terrain::kImages;
}
