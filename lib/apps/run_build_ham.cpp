#include "apps/run_build_ham.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>
#include <string_view>

#include "apps/describe_terrain_file.h"
#include "apps/stage.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#include "splatkit/remove_on_signal.h"
#include "terrain/compute_ham.h"
#include "terrain/encode_ham_tiles.h"
#include "terrain/terrain_images.h"
#include "terrain/terrain_map.h"

namespace splatkit::apps {

namespace {

using terrain::HeightmapSource;

std::unique_ptr<HeightmapSource> open_source(const BuildHamOptions& o) {
  if (o.raw.empty()) check_heightmap_kind(o.paths.input);
  return terrain::open_heightmap(o.paths.input, o.raw);
}

// Metres per texel (x, y) from the georeferencing: geographic degrees at the map's centre
// latitude, or a projected CRS's own units; null without georeferencing.
nlohmann::json texel_size(const nlohmann::json& geo, int64_t height) {
  if (!geo.is_object() || !geo.contains("pixel_scale") || geo["pixel_scale"].size() < 2)
    return nullptr;
  const double sx = geo["pixel_scale"][0].get<double>(), sy = geo["pixel_scale"][1].get<double>();
  if (!(sx > 0) || !(sy > 0)) return nullptr;
  const std::string crs = geo.value("crs", "");
  if (crs != "EPSG:4326") return {sx, sy};
  double north = 0;
  if (geo.contains("tiepoint") && geo["tiepoint"].size() >= 6)
    north = geo["tiepoint"][4].get<double>();
  else if (geo.contains("origin"))
    north = geo["origin"][1].get<double>();
  const double lat = (north - sy * double(height) / 2) * M_PI / 180;
  return {sx * 111320.0 * std::cos(lat), sy * 110574.0};
}

// The full-resolution HAM, written to a temporary file beside the target and renamed at the end
// (OpenEXR seeks back to write its tile offsets, so it cannot go through OutputFile).
class FullHamFile {
 public:
  FullHamFile(const std::string& path, const HeightmapSource& source, int tile,
              const nlohmann::json& header)
      : path_(path) {
    std::string pattern = path + ".tmp.XXXXXX.exr";
    std::vector<char> name(pattern.begin(), pattern.end());
    name.push_back(0);
    const int fd = ::mkstemps(name.data(), 4);
    if (fd < 0) throw_output(path, std::strerror(errno));
    ::close(fd);
    temp_ = name.data();
    guard_.emplace(temp_);
    const std::string why = terrain::terrain_images(path).open_row_writer(
        temp_, source.info().width, source.info().height, tile, header, writer_);
    if (!why.empty()) throw_output(path, why);
  }
  ~FullHamFile() {
    if (!temp_.empty()) ::unlink(temp_.c_str());
  }
  void write(int64_t rows, const float* data) {
    const std::string why = writer_->write(rows, data);
    if (!why.empty()) throw_output(path_, as_target(why));
  }
  // Writes out the last tiles and the offsets (where a full disk shows).
  void finish() {
    const std::string why = writer_->close();
    if (!why.empty()) throw_output(path_, as_target(why));
  }
  // The image library's message names the temporary file, which the user never sees: the
  // target's name instead.
  std::string as_target(std::string why) const {
    for (std::size_t at; !temp_.empty() && (at = why.find(temp_)) != std::string::npos;)
      why.replace(at, temp_.size(), path_);
    return why;
  }
  void commit() {
    // mkstemps made it 0600: the mode a new file gets (or the replaced file's), as OutputFile.
    struct stat st {};
    mode_t mode;
    if (::stat(path_.c_str(), &st) == 0) {
      mode = st.st_mode & 0777;
    } else {
      const mode_t mask = ::umask(0);
      ::umask(mask);
      mode = 0666 & ~mask;
    }
    ::chmod(temp_.c_str(), mode);
    if (std::rename(temp_.c_str(), path_.c_str()) != 0) throw_output(path_, std::strerror(errno));
    temp_.clear();
    guard_.reset();
  }

 private:
  std::string path_, temp_;
  std::optional<RemoveOnSignal> guard_;
  std::unique_ptr<terrain::RowWriter> writer_;
};

}  // namespace

StageSummary run_build_ham(const BuildHamOptions& o, const ProgressFn& progress) {
  const std::string& output = o.paths.output;
  if (!is_stream_path(output) && lower_extension(output) != "exr")
    throw_usage("OUT must end in .exr or be '-': " + output);
  if (!o.ham_full.empty() && lower_extension(o.ham_full) != "exr")
    throw_usage("--ham-full must end in .exr");
  // (in float, as the heights are scaled: 1e-50 would flatten the map to zeros)
  if (!(float(o.z_scale) > 0) || !std::isfinite(float(o.z_scale)))
    throw_usage("--z-scale must be > 0 and within the float range");
  if (o.tile < 1 || o.tile > 65536) throw_usage("--tile must be in [1, 65536]");
  Stage stage("build-ham", o.paths);
  stage.check_side_output("--ham-full", o.ham_full);
  std::unique_ptr<HeightmapSource> source =
      stage.phase(nullptr, "opening " + stage.input_name(), [&] { return open_source(o); });
  const terrain::HeightmapInfo& info = source->info();
  if (info.width > (int64_t(1) << 31) || info.height > (int64_t(1) << 31))
    throw_unsupported(stage.input_name(), "sides above 2^31 texels");

  terrain::HamOptions ho;
  ho.tile = o.tile;
  ho.z_scale = o.z_scale;
  if (o.nodata) {
    ho.has_nodata = true;
    ho.nodata = *o.nodata;
  }
  nlohmann::json header = {{"format", info.format},
                           {"sample_type", info.sample_type},
                           {"georef", info.georef},
                           {"texel_size", texel_size(info.georef, info.height)}};
  const bool has_nodata = ho.has_nodata || info.has_nodata;
  header["nodata"] = has_nodata ? nlohmann::json(ho.has_nodata ? ho.nodata : info.nodata)
                                : nlohmann::json(nullptr);

  std::unique_ptr<FullHamFile> full;
  if (!o.ham_full.empty()) full = std::make_unique<FullHamFile>(o.ham_full, *source, 64, header);
  terrain::HamStats stats;
  terrain::HamRowSink sink;
  if (full) sink = [&](int64_t rows, const float* data) { full->write(rows, data); };
  terrain::HamTiles tiles = stage.phase("ham", "computing the HAM", [&] {
    return terrain::compute_ham(*source, ho, stats, sink, progress);
  });
  for (const auto& [key, value] : header.items()) tiles.header[key] = value;

  const Clock::time_point t0 = Clock::now();
  const std::vector<unsigned char> bytes = terrain::encode_ham_tiles(tiles);
  OutputFile out(output);
  out.write(bytes.data(), bytes.size());
  if (full) full->finish();
  stage.record("write", seconds_since(t0));

  nlohmann::json report;
  if (!o.paths.report.empty()) {
    const double seconds = stage.seconds("ham");
    report = {{"options",
               {{"tile", o.tile},
                {"z_scale", o.z_scale},
                {"nodata", o.nodata ? nlohmann::json(*o.nodata) : nlohmann::json(nullptr)},
                {"raw", o.raw},
                {"ham_full", o.ham_full}}},
              {"width", info.width},
              {"height", info.height},
              {"tiles_x", tiles.tiles_x},
              {"tiles_y", tiles.tiles_y},
              {"samples", stats.samples},
              {"voids", stats.voids},
              {"void_rows", stats.void_rows},
              {"h_min", stats.h_min},
              {"h_max", stats.h_max},
              {"ham_max", stats.ham_max},
              {"band_rows", stats.band_rows},
              {"samples_per_second", seconds > 0 ? double(stats.samples) / seconds : 0.0},
              {"header", tiles.header}};
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  if (full) full->commit();
  std::ostringstream extra;
  extra << info.width << " x " << info.height << " " << info.sample_type << ", "
        << tiles.tiles_x * tiles.tiles_y << " tiles, " << stats.voids << " voids filled";
  return {stats.samples, "samples", extra.str()};
}

}  // namespace splatkit::apps
