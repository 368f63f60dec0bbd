#include "apps/run_splat_synth.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <memory>

#include "splatkit/error.h"
#include "splatkit/output_file.h"
#include "splatkit/synthetic_city.h"
#include "splatkit/version.h"

namespace splatkit::apps {

namespace {

nlohmann::json describe(const ShapeOptions& o, const SplatCloud& cloud, bool colors) {
  const Bounds b = compute_bounds(cloud);
  nlohmann::json m;
  m["tool"] = "splat-synth";
  m["version"] = kVersion;
  m["options"] = {{"shape", shape_kind_name(o.kind)},
                  {"points", o.points},
                  {"seed", o.seed},
                  {"noise", o.noise},
                  {"random", o.random || o.scan_lines > 1},
                  {"keep_inside", o.keep_inside},
                  {"colors", colors}};
  if (o.scan_lines > 1) m["options"]["scan_lines"] = o.scan_lines;
  if (o.texture) m["options"]["texture"] = true;
  m["counts"] = {{"points", cloud.size()}, {"faces", 0}};
  if (!b.empty())
    m["bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
  m["patches"] = shape_patch_names(o);
  m["history"] = nlohmann::json::array();
  return m;
}

nlohmann::json walkthrough_json(const std::vector<CityCamera>& cameras) {
  nlohmann::json path = nlohmann::json::array();
  for (const CityCamera& c : cameras)
    path.push_back(
        {{"eye", {c.eye.x, c.eye.y, c.eye.z}}, {"target", {c.target.x, c.target.y, c.target.z}}});
  return path;
}

StageSummary run_city(const SplatSynthOptions& o) {
  if (o.city_blocks < 2 || o.city_blocks > 64) throw_usage("--blocks must be in 2..64");
  if (o.walk_frames < 2 || o.walk_frames > 100000)
    throw_usage("--walk-frames must be in 2..100000");
  if (o.sample.points == 0) throw_usage("--points must be at least 1");
  if (o.sample.texture) throw_usage("--texture applies to the shapes, not the city");
  Stage stage("splat-synth", {"", o.output, o.report});
  stage.check_output_format(o.write);
  stage.check_side_output("--walkthrough", o.walkthrough);
  CityOptions city;
  city.points = o.sample.points;
  city.blocks = o.city_blocks;
  city.seed = o.sample.seed;
  city.walk_frames = o.walk_frames;
  LoadedCloud doc;
  doc.cloud = stage.phase(nullptr, "building the city", [&] { return make_city(city); });
  if (o.no_color) doc.cloud.colors.clear();
  doc.format = "synthetic";
  nlohmann::json m;
  m["tool"] = "splat-synth";
  m["version"] = kVersion;
  m["options"] = {{"shape", "city"},
                  {"points", o.sample.points},
                  {"blocks", o.city_blocks},
                  {"seed", o.sample.seed},
                  {"colors", !o.no_color}};
  m["counts"] = {{"points", doc.cloud.size()}, {"faces", 0}};
  m["history"] = nlohmann::json::array();
  doc.metadata = m;
  std::unique_ptr<OutputFile> walk;  // committed with OUT
  if (!o.walkthrough.empty()) {
    walk = std::make_unique<OutputFile>(o.walkthrough);
    walk->write(walkthrough_json(city_walkthrough(city)).dump(1) + "\n");
  }
  OutputFile* also[] = {walk.get()};
  stage.write(doc, o.write, {{"shape", "city"}, {"points", doc.cloud.size()}}, also);
  return {doc.cloud.size(), "points", ""};
}

}  // namespace

StageSummary run_splat_synth(const SplatSynthOptions& o, const ProgressFn& progress) {
  if (o.shape == "city") return run_city(o);
  const SplatSynthOptions defaults;
  if (!o.walkthrough.empty() || o.city_blocks != defaults.city_blocks ||
      o.walk_frames != defaults.walk_frames)
    throw_usage("--walkthrough, --blocks and --walk-frames apply to the city only");
  ShapeOptions sample = o.sample;
  sample.kind = parse_shape_kind(o.shape);
  if (sample.keep_inside && sample.kind != ShapeKind::kTwoSpheres)
    throw_usage("--keep-inside applies to two-spheres only");
  if (!(sample.noise >= 0 && sample.noise <= 1)) throw_usage("--noise must be a number in [0, 1]");
  if (sample.points == 0) throw_usage("--points must be at least 1");
  Stage stage("splat-synth", {"", o.output, o.report});
  stage.check_output_format(o.write);
  progress(0.0, "sampling");
  LoadedCloud doc;
  doc.cloud = stage.phase(nullptr, "sampling the shape", [&] { return make_shape(sample); });
  if (o.no_color) doc.cloud.colors.clear();
  doc.format = "synthetic";
  doc.metadata = describe(sample, doc.cloud, !o.no_color);
  stage.write(doc, o.write, {{"shape", o.shape}, {"points", doc.cloud.size()}});
  return {doc.cloud.size(), "points", ""};
}

}  // namespace splatkit::apps
