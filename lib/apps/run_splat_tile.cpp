#include "apps/run_splat_tile.h"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <new>
#include <numeric>
#include <system_error>

#include "apps/morton_tile_grid.h"
#include "apps/stage.h"
#include "formats/provenance.h"
#include "formats/write_cloud.h"
#include "splatkit/append_points.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"
#include "splatkit/output_file.h"
#include "splatkit/same_file.h"
#include "splatkit/seconds_since.h"
#include "splatkit/take_own_points.h"
#include "splatkit/tile_grid.h"
#include "splatkit/tile_halo.h"
#include "splatkit/version.h"

namespace splatkit::apps {

namespace fs = std::filesystem;

namespace {

constexpr const char* kTool = "splat-tile";
// The skyline beyond each side of a tile (formats/tiles.md): over a band of half a tile beyond
// the halo's edge, cut into kSkylineSegments along the side, the height of the highest point in
// each segment.
constexpr int kSkylineSegments = 32;
using Skyline = std::array<std::array<double, kSkylineSegments>, 4>;  // -x, +x, -y, +y

// Raises the skylines of the tiles whose band beyond a side holds (x, y, z).
void raise_skylines(double x, double y, double z, double size, double halo,
                    std::map<TileKey, Skyline>& skylines) {
  const double band = size / 2, reach = halo + band;
  const TileKey lo = tile_of(x - reach, y - reach, size), hi = tile_of(x + reach, y + reach, size);
  const double span = size + 2 * halo, step = span / kSkylineSegments;
  for (int64_t i = lo.i; i <= hi.i; ++i)
    for (int64_t j = lo.j; j <= hi.j; ++j) {
      const double x0 = static_cast<double>(i) * size - halo, x1 = x0 + span;
      const double y0 = static_cast<double>(j) * size - halo, y1 = y0 + span;
      const bool in_x = x >= x0 && x < x1, in_y = y >= y0 && y < y1;
      // (side, position along it) when the point lies in the band beyond that side
      int side = -1;
      double along = 0;
      if (in_y && x < x0 && x >= x0 - band) side = 0, along = y - y0;
      if (in_y && x >= x1 && x < x1 + band) side = 1, along = y - y0;
      if (in_x && y < y0 && y >= y0 - band) side = 2, along = x - x0;
      if (in_x && y >= y1 && y < y1 + band) side = 3, along = x - x0;
      if (side < 0) continue;
      auto it = skylines.find({i, j});
      if (it == skylines.end()) {
        Skyline empty;
        for (auto& a : empty) a.fill(-std::numeric_limits<double>::infinity());
        it = skylines.emplace(TileKey{i, j}, empty).first;
      }
      const int k = std::clamp(static_cast<int>(along / step), 0, kSkylineSegments - 1);
      double& top = it->second[static_cast<std::size_t>(side)][static_cast<std::size_t>(k)];
      top = std::max(top, z);
    }
}

nlohmann::json skyline_json(const Skyline& s, double band) {
  static const char* const kSides[4] = {"-x", "+x", "-y", "+y"};
  nlohmann::json out = {{"band", band}};
  for (int side = 0; side < 4; ++side) {
    nlohmann::json tops = nlohmann::json::array();
    for (double z : s[static_cast<std::size_t>(side)])
      tops.push_back(std::isfinite(z) ? nlohmann::json(z) : nlohmann::json());
    out[kSides[side]] = tops;
  }
  return out;
}

// How far from its origin a float32 position keeps half a millimetre (2^-11 m steps below 2^14 m).
constexpr double kFrameReach = 16384;

// The folder of the parts kept between the two passes, inside the output folder (same file
// system: no copy across disks); removed with what it holds when the run ends, however it ends.
class PartsDir {
 public:
  explicit PartsDir(const fs::path& parent) {
    std::string tmpl = (parent / ".splat-tile-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr)
      throw Error(ErrorKind::kOutput,
                  parent.string() + ": cannot create a temporary folder: " + std::strerror(errno));
    path_ = tmpl;
  }
  ~PartsDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  PartsDir(const PartsDir&) = delete;
  PartsDir& operator=(const PartsDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// A part file and the number of the input it came from.
struct Part {
  std::string path;
  std::size_t input;
};

// One tile's parts: per input, the files of its own points and of its halo points.
struct TileParts {
  std::vector<Part> own, halo;
  uint64_t own_points = 0, halo_points = 0;
  double first_z = 0;  // the height of the tile's first own point (file coordinates)
};

// Writes `indices` of `cloud` (in its own frame) as a .splk part.
void write_part(const SplatCloud& cloud, const std::vector<uint32_t>& indices,
                const std::string& name, const fs::path& path) {
  LoadedCloud part;
  part.format = "splk";
  part.cloud.origin = cloud.origin;
  append_points(part.cloud, cloud, indices, name);
  WriteOptions w;
  w.format = FileFormat::kSplk;
  write_cloud(part, path.string(), w);
}

// Reads the part files in order into `tile`; `names`: the inputs' names.
void append_parts(SplatCloud& tile, const std::vector<Part>& parts,
                  const std::vector<std::string>& names) {
  for (const Part& p : parts) {
    const LoadedCloud part = read_cloud(p.path);
    std::vector<uint32_t> all(part.cloud.size());
    std::iota(all.begin(), all.end(), 0u);
    append_points(tile, part.cloud, all, names[p.input]);
  }
}

nlohmann::json square_json(const TileKey& key, const TileGridFrame& grid) {
  const double x0 = grid.x0 + static_cast<double>(key.i) * grid.size,
               y0 = grid.y0 + static_cast<double>(key.j) * grid.size;
  return {{"min", {x0, y0}}, {"max", {x0 + grid.size, y0 + grid.size}}};
}

void check_options(const SplatTileOptions& o) {
  if (o.inputs.empty()) throw Error(ErrorKind::kUsage, "no input files");
  if (!(o.tile_size > 0) || !std::isfinite(o.tile_size))
    throw Error(ErrorKind::kUsage, "--tile-size must be a positive number");
  if (!std::isfinite(o.halo)) throw Error(ErrorKind::kUsage, "--halo must be a number");
  if (std::count(o.inputs.begin(), o.inputs.end(), "-") > 1)
    throw Error(ErrorKind::kUsage, "standard input ('-') given twice");
  if (o.morton_grid && std::count(o.inputs.begin(), o.inputs.end(), "-") > 0)
    throw Error(ErrorKind::kUsage, "--morton-grid reads the inputs twice: not with '-'");
  if (o.out_dir.empty() || o.out_dir == "-")
    throw Error(ErrorKind::kUsage, "-o needs a folder (standard output cannot hold tiles)");
}

// Creates out_dir (its parent must exist) and out_dir/tiles.
fs::path make_out_dir(const std::string& out_dir) {
  const fs::path dir(out_dir);
  std::error_code ec;
  fs::create_directory(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error(ErrorKind::kOutput,
                out_dir + ": cannot create the folder" + (ec ? ": " + ec.message() : ""));
  fs::create_directory(dir / "tiles", ec);
  if (ec || !fs::is_directory(dir / "tiles"))
    throw Error(ErrorKind::kOutput, (dir / "tiles").string() + ": cannot create the folder" +
                                        (ec ? ": " + ec.message() : ""));
  return dir;
}

// The box of every own point, file coordinates (float64 sums of an origin and a float32
// position: exact, so a reader gets the float32 bounds back in its frame).
struct SurveyBox {
  std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  void add(double x, double y, double z) {
    const double p[3] = {x, y, z};
    for (std::size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
  nlohmann::json json() const { return {{"min", lo}, {"max", hi}}; }
};

// What pass 2 needs of the whole run.
struct TileRun {
  TileGridFrame grid;
  double halo;
  std::array<double, 3> origin;  // the first input's
  const SurveyBox& survey;
  const std::vector<std::string>& input_names;
  const std::map<TileKey, Skyline>& skylines;
};

// Pass 2 for one tile that owns points: its parts gathered into dir/tiles/<name>.splk, in the
// tile's own frame, with the halo attribute and the metadata; returns its entry of tiles.json.
nlohmann::json write_tile(const fs::path& dir, const TileKey& key, const TileParts& t,
                          const TileRun& run) {
  const std::string name = tile_name(key);
  LoadedCloud doc;
  doc.format = "splk";
  SplatCloud& tile = doc.cloud;
  // The frame: the first input's (so that a tile's positions are the same float32 values as
  // in a run over the whole survey read from the same files), unless the tile lies farther
  // from it than float32 keeps millimetres; then one chosen at the square's corner as the
  // readers choose one (splat_cloud.h).
  const double corner[3] = {run.grid.x0 + static_cast<double>(key.i) * run.grid.size,
                            run.grid.y0 + static_cast<double>(key.j) * run.grid.size, t.first_z};
  tile.origin = run.origin;
  for (int a = 0; a < 3; ++a)
    if (!(std::fabs(corner[a] - run.origin[a]) + (a < 2 ? run.grid.size + run.halo : 0) <
          kFrameReach))
      tile.origin = choose_origin({corner[0], corner[1], corner[2]});
  append_parts(tile, t.own, run.input_names);
  append_parts(tile, t.halo, run.input_names);
  ExtraAttribute flag(kHaloAttribute, ScalarType::kUInt8);
  flag.values.resize(tile.size());
  for (std::size_t i = t.own_points; i < tile.size(); ++i) flag.values.set(i, 1);
  tile.extras.push_back(std::move(flag));
  // How high the survey reaches just beyond each side: estimate-normals' views do not look
  // through a border where the survey goes on.
  const auto sky = run.skylines.find(key);
  const std::string file = "tiles/" + name + ".splk";
  doc.metadata = {
      {"tool", kTool},
      {"version", kVersion},
      {"tile",
       {{"name", name},
        {"i", key.i},
        {"j", key.j},
        {"size", run.grid.size},
        {"halo", run.halo},
        {"square", square_json(key, run.grid)},
        {"survey_box", run.survey.json()},
        {"own_points", t.own_points},
        {"halo_points", t.halo_points},
        {"skyline", sky != run.skylines.end() ? skyline_json(sky->second, run.grid.size / 2)
                                              : nlohmann::json::object()}}},
      {"inputs", run.input_names}};
  WriteOptions w;
  w.format = FileFormat::kSplk;
  write_cloud(doc, (dir / file).string(), w);
  return {{"name", name},
          {"file", file},
          {"i", key.i},
          {"j", key.j},
          {"square", square_json(key, run.grid)},
          {"own_points", t.own_points},
          {"halo_points", t.halo_points}};
}

}  // namespace

StageSummary run_splat_tile(const SplatTileOptions& o, const ProgressFn& progress) {
  const Clock::time_point start = Clock::now();
  check_options(o);
  for (const std::string& in : o.inputs)
    if (in != "-" && !fs::exists(in)) throw Error(ErrorKind::kBadInput, in + ": no such file");
  const fs::path dir = make_out_dir(o.out_dir);
  const fs::path tiles_json = dir / "tiles.json";
  if (!o.report.empty()) {
    for (const std::string& in : o.inputs)
      if (in != "-" && same_file(in, o.report))
        throw Error(ErrorKind::kUsage, "--report names the input " + in);
    if (o.report != "-" && fs::absolute(o.report).parent_path() == fs::absolute(dir / "tiles"))
      throw Error(ErrorKind::kUsage, "--report must not go into the tiles folder");
    if (o.report != "-" && same_file(o.report, tiles_json.string()))
      throw Error(ErrorKind::kUsage, "--report names tiles.json");
    check_can_create(o.report);
  }
  const PartsDir parts_dir(dir);
  nlohmann::json timings = nlohmann::json::object();
  double halo = o.halo;
  std::string halo_rule = "given (--halo)";
  std::map<TileKey, TileParts> tiles;
  std::map<TileKey, Skyline> skylines;
  nlohmann::json inputs = nlohmann::json::array();
  std::vector<std::string> input_names;
  SplatCloud first_fields;  // one point of the first input: the fields every input must have
  uint64_t total = 0, skipped_halo = 0, faces_dropped = 0;
  std::vector<TileKey> around;
  SurveyBox survey;
  const double n_inputs = static_cast<double>(o.inputs.size());
  TileGridFrame grid{0, 0, o.tile_size};
  if (o.morton_grid) {  // a first pass for the survey's box
    SurveyBox box;
    for (const std::string& path : o.inputs) {
      InputStream in(path);
      LoadedCloud doc = read_cloud(in, o.read);
      const SplatCloud& cloud = doc.cloud;
      for (uint32_t i : take_own_points(doc.cloud))
        box.add(cloud.origin[0] + cloud.positions[i].x, cloud.origin[1] + cloud.positions[i].y,
                cloud.origin[2] + cloud.positions[i].z);
    }
    if (box.lo[0] <= box.hi[0]) grid = morton_tile_grid(box.lo, box.hi, o.tile_size);
  }

  // Pass 1: each input read whole, its points parted by tile.
  for (std::size_t a = 0; a < o.inputs.size(); ++a) {
    const std::string& path = o.inputs[a];
    const Clock::time_point t0 = Clock::now();
    InputStream in(path);
    const std::string name = in.name();
    LoadedCloud doc;
    try {
      doc = read_cloud(in, o.read, [&](double f, const char* phase) {
        if (f >= 0) progress((static_cast<double>(a) + 0.5 * f) / n_inputs * 0.7, phase);
      });
    } catch (const std::bad_alloc&) {
      throw Error(ErrorKind::kOutOfMemory, name + ": out of memory while reading");
    }
    SplatCloud& cloud = doc.cloud;
    faces_dropped += cloud.face_count();
    // The points this input gives: all but another tile's halo.
    const std::vector<uint32_t> keep = take_own_points(cloud);
    skipped_halo += cloud.size() - keep.size();
    if (a == 0 || first_fields.size() == 0) {
      first_fields = SplatCloud{};
      first_fields.origin = cloud.origin;
      if (cloud.size() > 0) append_points(first_fields, cloud, std::vector<uint32_t>{0}, name);
    } else if (cloud.size() > 0) {
      if (const std::string d = fields_difference(first_fields, cloud); !d.empty())
        throw Error(ErrorKind::kBadInput,
                    name + ": " + d + " (every input must hold the same fields)");
    }
    if (halo < 0 && keep.size() >= kTileHaloRow) {  // from the first input that can tell
      progress((static_cast<double>(a) + 0.5) / n_inputs * 0.7, "halo");
      halo = tile_halo(cloud.positions);
      halo_rule = "auto: twice the " + std::to_string(static_cast<int>(kTileHaloQuantile * 100)) +
                  "th percentile, over " + name + ", of the distance from a point to its " +
                  std::to_string(kTileHaloRow) + "th nearest";
    }
    // Each point's tile and the tiles whose halo holds it; a run of points in one tile costs one
    // map lookup.
    using Lists = std::pair<std::vector<uint32_t>, std::vector<uint32_t>>;  // own, halo
    std::map<TileKey, Lists> parts;
    TileKey last{};
    Lists* own = nullptr;  // the entry of `last` (map entries stay where they are)
    for (uint32_t i : keep) {
      const Vec3f& p = cloud.positions[i];
      const double x = cloud.origin[0] + p.x, y = cloud.origin[1] + p.y;
      const double z = cloud.origin[2] + p.z;
      survey.add(x, y, z);
      const TileKey key = tile_of(x - grid.x0, y - grid.y0, grid.size);
      if (own == nullptr || !(key == last)) own = &parts[last = key];
      own->first.push_back(i);
      around.clear();
      halo_tiles(x - grid.x0, y - grid.y0, grid.size, halo, around);
      for (const TileKey& k : around) parts[k].second.push_back(i);
      raise_skylines(x - grid.x0, y - grid.y0, z, grid.size, halo, skylines);
    }
    progress((static_cast<double>(a) + 0.75) / n_inputs * 0.7, "parting");
    for (const auto& [key, lists] : parts) {
      TileParts& t = tiles[key];
      const std::string stem = tile_name(key) + "-" + std::to_string(a);
      if (!lists.first.empty()) {
        const fs::path f = parts_dir.path() / (stem + "-own.splk");
        write_part(cloud, lists.first, name, f);
        if (t.own.empty()) t.first_z = cloud.origin[2] + cloud.positions[lists.first[0]].z;
        t.own.push_back({f.string(), a});
        t.own_points += lists.first.size();
      }
      if (!lists.second.empty()) {
        const fs::path f = parts_dir.path() / (stem + "-halo.splk");
        write_part(cloud, lists.second, name, f);
        t.halo.push_back({f.string(), a});
        t.halo_points += lists.second.size();
      }
    }
    total += keep.size();
    input_names.push_back(name);
    nlohmann::json record = input_record(in, doc.format);
    record["points"] = keep.size();
    inputs.push_back(record);
    timings["read_and_part"] = timings.value("read_and_part", 0.0) + seconds_since(t0);
  }
  if (halo < 0) halo = 0;

  // Pass 2: each tile's parts gathered into its file, in the tile's own frame.
  const Clock::time_point t1 = Clock::now();
  nlohmann::json tile_list = nlohmann::json::array();
  std::vector<std::string> written;
  std::size_t done = 0;
  const TileRun run{grid, halo, first_fields.origin, survey, input_names, skylines};
  for (const auto& [key, t] : tiles) {
    progress(0.7 + 0.3 * static_cast<double>(done++) / static_cast<double>(tiles.size()), "tiles");
    if (t.own_points == 0) continue;  // a halo without a tile: its points belong elsewhere
    const nlohmann::json entry = write_tile(dir, key, t, run);
    written.push_back(entry["name"].get<std::string>() + ".splk");
    tile_list.push_back(entry);
  }
  timings["tiles"] = seconds_since(t1);

  // Tiles of an earlier run into this folder that this run did not write.
  std::sort(written.begin(), written.end());
  std::size_t removed = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(dir / "tiles")) {
    const std::string f = e.path().filename().string();
    if (f.rfind("tile_", 0) == 0 && e.path().extension() == ".splk" &&
        !std::binary_search(written.begin(), written.end(), f)) {
      std::error_code ec;
      if (fs::remove(e.path(), ec)) ++removed;
    }
  }

  nlohmann::json index = {{"tool", kTool},
                          {"version", kVersion},
                          {"tile_size", grid.size},
                          {"halo", halo},
                          {"halo_rule", halo_rule},
                          {"grid", "tile (i, j) holds i*S <= x < (i+1)*S, j*S <= y < (j+1)*S"},
                          {"points", total},
                          {"tiles", tile_list},
                          {"inputs", inputs}};
  if (total > 0) index["survey_box"] = survey.json();
  if (o.morton_grid) {
    index["grid"] =
        "tile (i, j) holds X0 + i*S <= x < X0 + (i+1)*S, Y0 + j*S <= y < Y0 + (j+1)*S: the "
        "columns of the Morton cells of the survey box's cube";
    index["grid_origin"] = {grid.x0, grid.y0};
  }
  {
    OutputFile out(tiles_json.string());
    out.write(index.dump(2) + "\n");
    out.commit();
  }
  if (!o.report.empty()) {
    timings["command"] = seconds_since(start);
    nlohmann::json report = {{"tool", kTool},
                             {"output", o.out_dir},
                             {"tile_size", grid.size},
                             {"halo", halo},
                             {"points", total},
                             {"tiles", tile_list.size()},
                             {"halo_points_skipped", skipped_halo},
                             {"faces_dropped", faces_dropped},
                             {"stale_tiles_removed", removed},
                             {"inputs", inputs},
                             {"timings_s", timings},
                             {"peak_rss_bytes", peak_rss_bytes()}};
    OutputFile out(o.report);
    out.write(report.dump(2) + "\n");
    out.commit();
  }
  progress(1.0, "done");
  char extra[160];
  std::snprintf(extra, sizeof extra, "%zu tiles of %g, halo %g", tile_list.size(), grid.size, halo);
  return {total, "points", extra};
}

}  // namespace splatkit::apps
