#include "apps/describe_terrain_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>
#include <sstream>
#include <string_view>

#include "apps/texel_frame.h"
#include "formats/describe_common.h"
#include "formats/read_qsplat.h"
#include "formats/splk.h"
#include "formats/spt_codes.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "terrain/terrain_images.h"
#include "terrain/terrain_map.h"

namespace splatkit::apps {

namespace {

// The keys every splat-info report has (formats/describe_common.h): bytes, bounds of the texel
// centres in the file's coordinates (heights `z_lo`..`z_hi`, null when unknown), crs.
void add_common_keys(nlohmann::json& r, const std::string& path, int64_t width, int64_t height,
                     const nlohmann::json& georef, const nlohmann::json& z_lo,
                     const nlohmann::json& z_hi) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  if (!ec) r["bytes"] = bytes;
  const TexelFrame f = texel_frame(georef);
  const double xa = f.x0, xb = f.x0 + double(width - 1) * f.dx;
  const double ya = f.y0, yb = f.y0 + double(height - 1) * f.dy;
  r["bounds"] = {{"min", {std::min(xa, xb), std::min(ya, yb), z_lo}},
                 {"max", {std::max(xa, xb), std::max(ya, yb), z_hi}}};
  r["crs"] = georef.is_object() && georef.contains("crs") && georef["crs"].is_string()
                 ? georef["crs"]
                 : nlohmann::json(nullptr);
}

// The lowest and highest height of the map, no-data and NaN samples left out (read in bands of
// rows, as build-ham does); nulls when every sample is a void.
std::pair<nlohmann::json, nlohmann::json> height_range(terrain::HeightmapSource& source) {
  const terrain::HeightmapInfo& info = source.info();
  const int64_t band = std::max<int64_t>(1, info.band_rows);
  std::vector<float> rows(std::size_t(band * info.width));
  float lo = INFINITY, hi = -INFINITY;
  for (int64_t y = 0; y < info.height; y += band) {
    const int64_t n = std::min(band, info.height - y);
    source.read_rows(n, rows.data());
    for (std::size_t i = 0; i < std::size_t(n * info.width); ++i) {
      const float v = rows[i];
      if (std::isnan(v) || (info.has_nodata && double(v) == info.nodata)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!(lo <= hi)) return {nullptr, nullptr};
  return {lo, hi};
}

}  // namespace

nlohmann::json describe_terrain_file(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != "tif" && ext != "tiff" && ext != "png" && ext != "exr" && ext != "hgt") return nullptr;
  if (ext == "exr") {
    // build-ham's tiles carry their own header; any other EXR is a heightmap.
    try {
      const terrain::HamTiles t = terrain::read_ham_tiles(path);
      nlohmann::json r = {{"file", path},        {"format", "ham"},
                          {"width", t.width},    {"height", t.height},
                          {"tile", t.tile},      {"tiles", {t.tiles_x, t.tiles_y}},
                          {"z_scale", t.z_scale}};
      for (const char* key : {"h_min", "h_max", "ham_max", "voids", "nodata", "georef"})
        if (t.header.contains(key)) r[key] = t.header[key];
      r["entries"] = int64_t(t.tiles_x) * int64_t(t.tiles_y);  // the tiles
      add_common_keys(r, path, t.width, t.height, r.value("georef", nlohmann::json()),
                      r.value("h_min", nlohmann::json()), r.value("h_max", nlohmann::json()));
      tidy_report_numbers(r);
      return r;
    } catch (const Error& e) {  // an EXR without the tiles' header is a heightmap
      if (e.kind() != ErrorKind::kBadInput ||
          std::string_view(e.what()).find(terrain::kNotHamTiles) == std::string_view::npos)
        throw;
    }
  }
  const std::unique_ptr<terrain::HeightmapSource> source = terrain::open_heightmap(path, "");
  const terrain::HeightmapInfo& info = source->info();
  nlohmann::json r = {
      {"file", path},
      {"format", "heightmap"},
      {"file_format", info.format},
      {"width", info.width},
      {"height", info.height},
      {"points", info.width * info.height},  // the samples
      {"sample_type", info.sample_type},
      {"nodata", info.has_nodata ? nlohmann::json(info.nodata) : nlohmann::json(nullptr)},
      {"georef", info.georef}};
  const auto [lo, hi] = height_range(*source);
  add_common_keys(r, path, info.width, info.height, info.georef, lo, hi);
  tidy_report_numbers(r);
  return r;
}

std::string describe_terrain_text(const nlohmann::json& r) {
  std::ostringstream s;
  if (r["format"] == "ham") {
    s << describe_common_text(r, "ham (build-ham tiles, EXR)",
                              report_number(r["tiles"][0]) + " x " + report_number(r["tiles"][1]) +
                                  " tiles")
      << "Map: " << r["width"] << " x " << r["height"] << " texels\n"
      << "Tiles: " << r["tiles"][0] << " x " << r["tiles"][1] << " of " << r["tile"] << " texels\n"
      << "Z scale: " << report_number(r["z_scale"]) << "\n";
    if (r.contains("h_min") && r.contains("h_max"))
      s << "Heights: " << report_number(r["h_min"]) << " .. " << report_number(r["h_max"]) << "\n";
    if (r.contains("ham_max")) s << "Largest HAM: " << report_number(r["ham_max"]) << "\n";
    if (r.contains("voids")) s << "Voids filled: " << r["voids"] << "\n";
  } else {
    s << describe_common_text(r, "heightmap (" + r["file_format"].get<std::string>() + ", " +
                                     r["sample_type"].get<std::string>() + ")",
                              "samples")
      << "Map: " << r["width"] << " x " << r["height"] << " texels\n";
  }
  if (r.contains("nodata") && !r["nodata"].is_null())
    s << "No-data: " << report_number(r["nodata"]) << "\n";
  // The georeferencing in brief (--json gives it whole): the CRS and the texel size.
  if (r.contains("georef") && r["georef"].is_object()) {
    const nlohmann::json& g = r["georef"];
    s << "Georeferencing: "
      << (g.contains("crs") && g["crs"].is_string() ? g["crs"].get<std::string>() : "yes");
    const nlohmann::json scale = g.value("pixel_scale", nlohmann::json());
    if (scale.is_array() && scale.size() >= 2 && scale[0].is_number() && scale[1].is_number())
      s << ", texels " << report_number(scale[0]) << " x " << report_number(scale[1]);
    s << "\n";
  }
  return s.str();
}

std::string non_heightmap_kind(const std::string& path) {
  if (path == "-") return "";
  std::ifstream in(path, std::ios::binary);
  char buf[16] = {};
  in.read(buf, sizeof buf);
  const std::string_view head(buf, static_cast<std::size_t>(in.gcount()));
  if (looks_like_qsplat(head)) return "a QSplat hierarchy (.qs)";
  if (spt::looks_like_spt(head)) return "a Sequential Point Tree (.spt)";
  if (is_splk_magic(head)) return "a splat file (.splk)";
  if (head.starts_with("ply\n") || head.starts_with("ply\r")) return "a PLY file";
  if (head.starts_with("LASF")) return "a LAS/LAZ point cloud";
  return "";
}

void check_heightmap_kind(const std::string& path) {
  const std::string kind = non_heightmap_kind(path);
  if (!kind.empty())
    throw_unsupported(path, kind + ", not a heightmap (GeoTIFF/TIFF, PNG, EXR, SRTM .hgt, or "
                                   "headerless RAW with --raw)");
}

}  // namespace splatkit::apps
