#include "apps/run_terrain_view.h"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "apps/describe_terrain_file.h"
#include "apps/parse_triple.h"
#include "apps/stage.h"
#include "apps/texel_frame.h"
#include "render/write_image.h"
#include "splatkit/error.h"
#include "terrain/ham_tiles_mismatch.h"
#include "terrain/render_terrain.h"
#include "terrain/terrain_images.h"

namespace splatkit::apps {

namespace {

Vec3f to_vec3(const std::array<double, 3>& v) { return {float(v[0]), float(v[1]), float(v[2])}; }

// --view AZ,EL[,DIST].
std::array<float, 3> parse_view(const std::string& text) {
  std::array<float, 3> v{0, 0, -1};
  float az = 0, el = 0, dist = 0;
  char extra = 0;
  const int n = std::sscanf(text.c_str(), "%f,%f,%f%c", &az, &el, &dist, &extra);
  if ((n != 2 && n != 3) || !std::isfinite(az) || !std::isfinite(el) ||
      (n == 3 && !(dist > 0 && std::isfinite(dist))))
    throw_usage("--view needs AZ,EL or AZ,EL,DIST (numbers, DIST > 0), got '" + text + "'");
  v = {az, el, n == 3 ? dist : -1.0f};
  return v;
}

using FileFrame = TexelFrame;

// A point in the file's coordinates, in the frame the terrain is drawn in: metres (texel sizes
// from the tiles) east and north of the north-west texel, heights times z_scale.
Vec3f to_view(const std::array<double, 3>& p, const FileFrame& f, const terrain::TerrainFrame& v,
              double z_scale) {
  const double column = (p[0] - f.x0) / f.dx, row = (p[1] - f.y0) / f.dy;
  return to_vec3({column * v.sx, -row * v.sy, p[2] * z_scale});
}

render::Camera make_camera(const SplatViewOptions& o, const render::BoundingSphere& bounds,
                           const FileFrame& file, const terrain::TerrainFrame& view,
                           double z_scale) {
  const Vec3f up = o.up.empty() ? Vec3f{0, 0, 1} : to_vec3(parse_triple(o.up, "--up"));
  if (!o.eye.empty()) {
    render::Camera c;
    c.eye = to_view(parse_triple(o.eye, "--eye"), file, view, z_scale);
    c.target = o.target.empty() ? bounds.center
                                : to_view(parse_triple(o.target, "--target"), file, view, z_scale);
    for (const Vec3f& v : {c.eye, c.target})
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw_usage("--eye and --target must lie within float range in the view's metres (" +
                    file.name + ")");
    if (!(norm(c.target - c.eye) > 0)) throw_usage("--eye and --target must differ");
    c.up = o.up.empty() ? render::automatic_up(c.target - c.eye, up) : up;
    c.fov_y_deg = o.fov_y_deg;
    c.width = o.width;
    c.height = o.height;
    return c;
  }
  std::array<float, 3> v{30.0f, 35.0f, -1.0f};
  if (!o.view.empty()) v = parse_view(o.view);
  std::optional<float> distance;
  if (v[2] > 0) distance = v[2];
  return render::orbit_camera(bounds, v[0], v[1], distance, up, o.fov_y_deg, o.width, o.height);
}

Vec3f parse_background(const std::string& text) {
  const std::array<double, 3> c = parse_triple(text, "--background", "r,g,b");
  for (double x : c)
    if (!(x >= 0 && x <= 1)) throw_usage("--background components must be in [0, 1]: " + text);
  return to_vec3(c);
}

// Metres per texel from the tiles' header (build-ham derives it from the georeferencing), else 1.
std::array<double, 2> texel_size(const terrain::HamTiles& t) {
  const auto it = t.header.find("texel_size");
  if (it != t.header.end() && it->is_array() && it->size() == 2 && (*it)[0].is_number() &&
      (*it)[1].is_number()) {
    const double sx = (*it)[0].get<double>(), sy = (*it)[1].get<double>();
    if (sx > 0 && sy > 0 && std::isfinite(sx) && std::isfinite(sy)) return {sx, sy};
  }
  return {1.0, 1.0};
}

}  // namespace

StageSummary run_terrain_view(const SplatViewOptions& o, const TerrainViewOptions& t,
                              const ProgressFn& progress) {
  if (t.ham.empty()) throw_usage("--terrain needs --ham TILES.exr (build-ham's output)");
  if (!o.input.empty()) throw_usage("--terrain renders a heightmap: give no splat file");
  if (o.turntable > 0) throw_usage("--turntable does not apply to --terrain");
  if (!o.path.empty()) throw_usage("--path does not apply to --terrain");
  if (o.occlusion != "none") throw_usage("--occlusion does not apply to --terrain");
  if (!(t.tess_error_px > 0)) throw_usage("--tess-error must be > 0");
  if (!(o.fov_y_deg > 0 && o.fov_y_deg < 180)) throw_usage("--fov must be in (0, 180) degrees");
  check_single_image_name(o.output);
  render::check_output_format(o.output);
  Stage stage("splat-view", {t.heightmap, o.output, o.stats_path}, "--stats");
  const terrain::HamTiles tiles =
      stage.phase("read", "reading " + t.ham, [&] { return terrain::read_ham_tiles(t.ham); });
  std::optional<double> nodata;
  if (tiles.header.contains("nodata") && tiles.header["nodata"].is_number())
    nodata = tiles.header["nodata"].get<double>();
  const terrain::TerrainMap map = stage.phase("read", "reading " + stage.input_name(), [&] {
    if (t.raw.empty()) check_heightmap_kind(t.heightmap);
    auto source = terrain::open_heightmap(t.heightmap, t.raw);
    return terrain::load_terrain_map(*source, nodata, tiles.z_scale);
  });
  if (map.width != tiles.width || map.height != tiles.height)
    throw_bad_input(t.ham, "tiles of a " + std::to_string(tiles.width) + " x " +
                               std::to_string(tiles.height) + " map, not of " + stage.input_name() +
                               " (" + std::to_string(map.width) + " x " +
                               std::to_string(map.height) + ")");
  if (const std::string why = terrain::ham_tiles_mismatch(map, tiles); !why.empty())
    throw_bad_input(t.ham, "not the tiles of " + stage.input_name() +
                               " (built from another heightmap): " + why);
  progress(0.3, "render");
  terrain::TerrainFrame frame;
  const auto [sx, sy] = texel_size(tiles);
  frame.sx = sx;
  frame.sy = sy;
  frame.h_min = map.h_min;
  for (float h : tiles.ham_max) frame.ham_ref = std::max(frame.ham_ref, double(h));
  terrain::TerrainRenderOptions ro;
  ro.tess.error_px = t.tess_error_px;
  ro.tess.d_max_tiles = t.tess_distance_tiles;
  ro.wireframe = t.wireframe;
  if (!o.background.empty()) ro.background = parse_background(o.background);
  const nlohmann::json georef =
      tiles.header.contains("georef") ? tiles.header["georef"] : nlohmann::json(nullptr);
  const FileFrame file = texel_frame(georef);
  const render::Camera camera =
      make_camera(o, terrain::terrain_bounds(map, frame), file, frame, tiles.z_scale);
  render::Framebuffer fb;
  fb.allocate(o.width, o.height, render::planes_for_output(o.output));
  const terrain::TerrainRenderStats stats = stage.phase("render", "rendering", [&] {
    return terrain::render_terrain(map, tiles, frame, camera, ro, fb);
  });
  const Clock::time_point t0 = Clock::now();
  OutputFile out(o.output);
  render::write_image(fb, out);
  stage.record("write", seconds_since(t0));
  nlohmann::json report;
  if (!o.stats_path.empty()) {
    nlohmann::json histogram = nlohmann::json::object();
    for (std::size_t k = 1; k < stats.histogram.size(); ++k)
      if (stats.histogram[k] > 0) histogram[std::to_string(k)] = stats.histogram[k];
    report = {
        {"mode", "terrain"},
        {"heightmap", stage.input_name()},
        {"ham", t.ham},
        {"width", o.width},  // the image's, as in splat mode; the heightmap's below
        {"height", o.height},
        {"map_width", map.width},
        {"map_height", map.height},
        {"tile", tiles.tile},
        {"texel_size", {sx, sy}},
        {"tess_error_px", t.tess_error_px},
        {"tess_distance_tiles", t.tess_distance_tiles},
        {"wireframe", t.wireframe},
        {"camera",
         {{"eye", {camera.eye.x, camera.eye.y, camera.eye.z}},
          {"target", {camera.target.x, camera.target.y, camera.target.z}},
          {"frame", "metres east and north of the north-west texel, heights times z_scale"},
          {"options_frame", file.name},
          {"fov_y_deg", camera.fov_y_deg}}},
        {"tiles", stats.tiles},
        {"visible_tiles", stats.visible_tiles},
        {"triangles", stats.triangles},
        {"triangles_at_64", stats.triangles_at_64},
        {"triangles_ratio",
         stats.triangles_at_64 > 0 ? double(stats.triangles) / double(stats.triangles_at_64) : 0.0},
        {"triangles_behind_near_plane", stats.triangles_behind},
        {"factor_histogram", histogram}};
  }
  OutputFile* outputs[] = {&out};
  stage.commit(outputs, std::move(report));
  if (stats.triangles == 0)
    std::fprintf(stderr,
                 "splat-view: warning: %s: the frame draws no terrain (0 triangles): the camera "
                 "sees none of %s (--eye and --target are in the file's coordinates, %s)\n",
                 display_name(o.output, true).c_str(), stage.input_name().c_str(),
                 file.name.c_str());
  std::ostringstream extra;
  extra << stats.visible_tiles << " of " << stats.tiles << " tiles visible, " << stats.triangles
        << " triangles (" << stats.triangles_at_64 << " at factor 64)";
  return {stats.triangles, "triangles", extra.str()};
}

}  // namespace splatkit::apps
