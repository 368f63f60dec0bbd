#include "apps/describe_terrain_file.h"

#include <fstream>
#include <sstream>
#include <string_view>

#include "formats/read_qsplat.h"
#include "formats/splk.h"
#include "formats/spt_codes.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "terrain/terrain_images.h"
#include "terrain/terrain_map.h"

namespace splatkit::apps {

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
      return r;
    } catch (const Error& e) {  // an EXR without the tiles' header is a heightmap
      if (e.kind() != ErrorKind::kBadInput ||
          std::string_view(e.what()).find(terrain::kNotHamTiles) == std::string_view::npos)
        throw;
    }
  }
  const std::unique_ptr<terrain::HeightmapSource> source = terrain::open_heightmap(path, "");
  const terrain::HeightmapInfo& info = source->info();
  return {{"file", path},
          {"format", "heightmap"},
          {"file_format", info.format},
          {"width", info.width},
          {"height", info.height},
          {"sample_type", info.sample_type},
          {"nodata", info.has_nodata ? nlohmann::json(info.nodata) : nlohmann::json(nullptr)},
          {"georef", info.georef}};
}

std::string describe_terrain_text(const nlohmann::json& r) {
  std::ostringstream s;
  s << "File: " << r["file"].get<std::string>() << "\n";
  if (r["format"] == "ham") {
    s << "Format: build-ham tiles (EXR)\n"
      << "Map: " << r["width"] << " x " << r["height"] << " texels\n"
      << "Tiles: " << r["tiles"][0] << " x " << r["tiles"][1] << " of " << r["tile"] << " texels\n"
      << "Z scale: " << r["z_scale"] << "\n";
    if (r.contains("h_min") && r.contains("h_max"))
      s << "Heights: " << r["h_min"] << " .. " << r["h_max"] << "\n";
    if (r.contains("ham_max")) s << "Largest HAM: " << r["ham_max"] << "\n";
    if (r.contains("voids")) s << "Voids filled: " << r["voids"] << "\n";
  } else {
    s << "Format: heightmap (" << r["file_format"].get<std::string>() << ", "
      << r["sample_type"].get<std::string>() << ")\n"
      << "Map: " << r["width"] << " x " << r["height"] << " texels\n";
  }
  if (r.contains("nodata") && !r["nodata"].is_null()) s << "No-data: " << r["nodata"] << "\n";
  // The georeferencing in brief (--json gives it whole): the CRS and the texel size.
  if (r.contains("georef") && r["georef"].is_object()) {
    const nlohmann::json& g = r["georef"];
    s << "Georeferencing: "
      << (g.contains("crs") && g["crs"].is_string() ? g["crs"].get<std::string>() : "yes");
    const nlohmann::json scale = g.value("pixel_scale", nlohmann::json());
    if (scale.is_array() && scale.size() >= 2 && scale[0].is_number() && scale[1].is_number())
      s << ", texels " << scale[0].get<double>() << " x " << scale[1].get<double>();
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
