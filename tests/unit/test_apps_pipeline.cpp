// The stages of lib/apps run on real files, each one reading what the one before wrote:
// splat-synth -> splat-convert -> estimate-normals -> build-splat-graph -> segment-surfaces ->
// splat-view, plus each stage's own rejections.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/run_build_qsplat.h"
#include "apps/run_build_splat_graph.h"
#include "apps/run_build_spt.h"
#include "apps/run_estimate_normals.h"
#include "apps/run_segment_surfaces.h"
#include "apps/run_splat_convert.h"
#include "apps/run_splat_info.h"
#include "apps/run_splat_view.h"
#include "formats/write_cloud.h"
#include "graph_io/graph_chunks.h"
#include "test_apps_support.h"

namespace splatkit::apps {
namespace {

namespace fs = std::filesystem;
using test::expect_stage_error;
using test::slurp;
using test::temp_path;

nlohmann::json read_json(const std::string& path) { return nlohmann::json::parse(slurp(path)); }

TEST(AppsSplatConvert, RoundTripThroughEveryWritableFormat) {
  const std::string ply = temp_path("convert", "t.ply");
  test::synth("torus", ply, 1500);
  const LoadedCloud original = read_cloud(ply);
  SplatConvertOptions o;
  o.paths = {ply, temp_path("convert", "t.splk"), ""};
  EXPECT_EQ(run_splat_convert(o).count, original.cloud.size());
  o.paths = {o.paths.output, temp_path("convert", "t2.ply"), ""};
  run_splat_convert(o);
  const LoadedCloud back = read_cloud(o.paths.output);
  ASSERT_EQ(back.cloud.size(), original.cloud.size());
  EXPECT_EQ(back.cloud.positions, original.cloud.positions);
  EXPECT_EQ(back.cloud.normals, original.cloud.normals);
  EXPECT_EQ(back.cloud.radii, original.cloud.radii);
  // An output format it cannot write is refused before the input is even opened.
  o.paths = {temp_path("convert", "missing.ply"), temp_path("convert", "t.pcd"), ""};
  expect_stage_error([&] { run_splat_convert(o); }, ErrorKind::kUnsupported,
                     "writing pcd is not supported");
  // Extensions in any case; one that names no format is refused (not written as .splk).
  o.paths = {ply, temp_path("convert", "T.PLY"), ""};
  run_splat_convert(o);
  EXPECT_EQ(read_cloud(o.paths.output).format, "ply");
  o.paths = {ply, temp_path("convert", "t.foo"), ""};
  expect_stage_error([&] { run_splat_convert(o); }, ErrorKind::kUsage,
                     "OUT's extension names no format");
  EXPECT_FALSE(fs::exists(o.paths.output));
  // Options for another format than the one written are refused, not ignored.
  o.paths = {ply, temp_path("convert", "t.xyz"), ""};
  o.write.ascii = true;
  expect_stage_error([&] { run_splat_convert(o); }, ErrorKind::kUsage, "--ascii is for PLY");
  o.write.ascii = false;
  o.write.las_format = 3;
  expect_stage_error([&] { run_splat_convert(o); }, ErrorKind::kUsage,
                     "--las-format is for LAS or LAZ output");
  EXPECT_FALSE(fs::exists(o.paths.output));
}

// A file of no points is refused by every tool that makes splats of it (a cloud without normals
// would only fail the next tool, with a message about normals); output names in any case.
TEST(AppsEstimateNormals, EmptyInputIsRefusedAndExtensionsInAnyCase) {
  const std::string empty = temp_path("normals", "empty.xyz");
  std::ofstream(empty) << "# x y z\n";
  EstimateNormalsOptions o;
  o.paths = {empty, temp_path("normals", "e.splk"), ""};
  expect_stage_error([&] { run_estimate_normals(o); }, ErrorKind::kBadInput,
                     "empty.xyz: the file has no points");
  const std::string in = temp_path("normals", "c.ply");
  test::synth("cube", in, 500);
  o.paths = {in, temp_path("normals", "C.SPLK"), ""};
  run_estimate_normals(o);
  EXPECT_EQ(read_cloud(o.paths.output).format, "splk");
}

TEST(AppsEstimateNormals, SphereGetsRadialNormalsAndAReport) {
  const std::string in = temp_path("normals", "s.ply");
  test::synth("sphere", in, 4000, 0.001);  // its exact normals are replaced by estimated ones
  EstimateNormalsOptions o;
  o.paths = {in, temp_path("normals", "s.splk"), temp_path("normals", "s.json")};
  const StageSummary s = run_estimate_normals(o);
  const LoadedCloud out = read_cloud(o.paths.output);
  ASSERT_EQ(out.cloud.size(), s.count);
  ASSERT_TRUE(out.cloud.has_normals());
  const Vec3f c = compute_bounds(out.cloud).center();
  std::size_t radial = 0;
  for (std::size_t i = 0; i < out.cloud.size(); ++i)
    radial += dot(normalized(out.cloud.positions[i] - c), out.cloud.normals[i]) > 0.9f;
  EXPECT_GT(radial, out.cloud.size() * 98 / 100);
  const nlohmann::json report = read_json(o.paths.report);
  EXPECT_EQ(report["tool"], "estimate-normals");
  EXPECT_EQ(report["output_points"], out.cloud.size());
  EXPECT_TRUE(report["timings_s"].contains("read"));
  EXPECT_TRUE(report["timings_s"].contains("write"));
  EXPECT_GT(report["peak_rss_bytes"].get<uint64_t>(), 0u);
  EXPECT_EQ(out.metadata["tool"], "estimate-normals");
  EXPECT_EQ(out.metadata["options"], report["options"]);
}

TEST(AppsEstimateNormals, NeverOverwritesItsInputAndChecksPathsFirst) {
  const std::string in = temp_path("normals", "m.ply");
  test::synth("cube", in, 1000);
  const std::string before = slurp(in);
  const fs::path dir = fs::path(in).parent_path();
  EstimateNormalsOptions o;
  o.paths = {in, (dir / "." / "m.ply").string(), ""};
  expect_stage_error([&] { run_estimate_normals(o); }, ErrorKind::kUsage, "never overwritten");
  o.paths = {in, (dir / "o.ply").string(), (dir / "no" / "r.json").string()};
  expect_stage_error([&] { run_estimate_normals(o); }, ErrorKind::kOutput, "r.json");
  EXPECT_FALSE(fs::exists(dir / "o.ply"));  // the report's failure left no OUT
  o.paths.report = "";
  o.viewpoint = "nan,0,0";
  expect_stage_error([&] { run_estimate_normals(o); }, ErrorKind::kUsage,
                     "--viewpoint must be three finite numbers");
  o.viewpoint = "";
  o.normals.radius_scale = std::numeric_limits<float>::infinity();
  expect_stage_error([&] { run_estimate_normals(o); }, ErrorKind::kUsage, "--radius-scale");
  EXPECT_EQ(slurp(in), before);
}

// cube (exact normals) -> graph -> surfaces: six faces.
struct CubeGraph {
  std::string graph;
  fs::path dir;
};

CubeGraph cube_graph() {
  CubeGraph c;
  const std::string cube = temp_path("graph", "cube.splk");
  c.dir = fs::path(cube).parent_path();
  test::synth("cube", cube, 6000, 0.0, false);
  BuildSplatGraphOptions o;
  o.paths = {cube, (c.dir / "cube-graph.splk").string(), (c.dir / "graph.json").string()};
  run_build_splat_graph(o);
  c.graph = o.paths.output;
  return c;
}

TEST(AppsBuildSplatGraph, WritesTheGraphChunksAndTheReport) {
  const CubeGraph c = cube_graph();
  const LoadedCloud doc = read_cloud(c.graph);
  ASSERT_NE(graph::find_chunk(doc, graph::kGraphChunkType), nullptr);
  ASSERT_NE(graph::find_chunk(doc, graph::kClassChunkType), nullptr);
  ASSERT_NE(graph::find_chunk(doc, graph::kClipChunkType), nullptr);
  const nlohmann::json report = read_json((c.dir / "graph.json").string());
  EXPECT_EQ(report["splats"], doc.cloud.size());
  EXPECT_GT(report["sharp_edges"].get<uint64_t>(), 0u);
  EXPECT_EQ(report["surfaces"], 6);
  EXPECT_EQ(doc.metadata["history"].size(), 1u);  // splat-synth's
}

TEST(AppsBuildSplatGraph, RejectsSplatsOtherToolsReject) {
  const std::string in = temp_path("graph", "bad.splk");
  test::synth("sphere", in, 300);
  LoadedCloud doc = read_cloud(in);
  doc.cloud.normals[17] = {0, 0, 0};
  write_cloud(doc, in);
  BuildSplatGraphOptions o;
  o.paths = {in, temp_path("graph", "o.splk"), ""};
  expect_stage_error([&] { run_build_splat_graph(o); }, ErrorKind::kBadInput,
                     in + ": splat 17: normal is zero");
  SplatViewOptions v;
  v.input = in;
  v.output = temp_path("graph", "o.png");
  expect_stage_error([&] { run_splat_view(v); }, ErrorKind::kBadInput,
                     in + ": splat 17: normal is zero");
  doc.cloud.normals[17] = {0, 0, 1};
  doc.cloud.radii[3] = -1;
  write_cloud(doc, in);
  expect_stage_error([&] { run_build_splat_graph(o); }, ErrorKind::kBadInput,
                     in + ": splat 3: radius -1 is negative");
}

TEST(AppsSegmentSurfaces, CubeHasSixFacesAndMinSizeDropsNone) {
  const CubeGraph c = cube_graph();
  SegmentSurfacesOptions o;
  o.paths = {c.graph, (c.dir / "surf.splk").string(), (c.dir / "surf.json").string()};
  o.method = "components";
  EXPECT_EQ(run_segment_surfaces(o).extra, "6 surfaces");
  const LoadedCloud doc = read_cloud(o.paths.output);
  const graph::Segmentation seg = graph::decode_surface_chunk(
      *graph::find_chunk(doc, graph::kSurfaceChunkType), doc.cloud.size(), "surf");
  EXPECT_EQ(seg.count(), 6u);
  const nlohmann::json report = read_json(o.paths.report);
  EXPECT_EQ(report["segments"], 6);
  EXPECT_EQ(report["unassigned_splats"], 0);
  EXPECT_EQ(report["segments_before_min_size"], 6);
  EXPECT_EQ(report["segments_segmented"], 6);
  EXPECT_EQ(report["refine"]["planes"], 6);  // every face explained by its plane
  EXPECT_EQ(report["refine"]["joined"], 0);
  EXPECT_EQ(report["refine"]["split"], 0);
  EXPECT_TRUE(report["timings_s"].contains("refine"));
  EXPECT_TRUE(report["timings_s"].contains("merge"));
  o.paths.output = (c.dir / "surf.ply").string();
  o.min_size = doc.cloud.size();  // larger than any face: no surface left
  EXPECT_EQ(run_segment_surfaces(o).extra, "0 surfaces");
  o.min_size = 1;
  o.merge_below = 0;
  expect_stage_error([&] { run_segment_surfaces(o); }, ErrorKind::kUsage,
                     "--merge-below must be >= 1");
}

// Converting to a format without chunks keeps the surface ids and splat classes as the
// attributes segment-surfaces writes into PLY (surface_id, class); .splk keeps the chunks.
TEST(AppsSplatConvert, SurfaceIdsAndClassesBecomeAttributes) {
  const CubeGraph c = cube_graph();
  SegmentSurfacesOptions s;
  s.paths = {c.graph, (c.dir / "surf.splk").string(), ""};
  run_segment_surfaces(s);
  const LoadedCloud doc = read_cloud(s.paths.output);
  const graph::Segmentation seg = graph::decode_surface_chunk(
      *graph::find_chunk(doc, graph::kSurfaceChunkType), doc.cloud.size(), "surf");
  const std::vector<graph::SplatClass> classes = graph::decode_class_chunk(
      *graph::find_chunk(doc, graph::kClassChunkType), doc.cloud.size(), "surf");
  SplatConvertOptions o;
  for (const char* ext : {"ply", "xyz"}) {
    o.paths = {s.paths.output, (c.dir / (std::string("surf.") + ext)).string(), ""};
    EXPECT_EQ(run_splat_convert(o).extra, std::string(ext) +
                                              " does not keep neighbour graph (GRPH), clip "
                                              "partners (CLIP)");
    const LoadedCloud back = read_cloud(o.paths.output);
    const ExtraAttribute* ids = back.cloud.find_extra("surface_id");
    const ExtraAttribute* cls = back.cloud.find_extra("class");
    ASSERT_NE(ids, nullptr);
    ASSERT_NE(cls, nullptr);
    ASSERT_EQ(ids->values.size(), seg.surface.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < seg.surface.size(); ++i)
      differ +=
          ids->values[i] != seg.surface[i] || cls->values[i] != static_cast<double>(classes[i]);
    EXPECT_EQ(differ, 0u) << ext;
  }
  // Into .splk the chunks stay chunks; LAS keeps neither chunks nor these attributes.
  o.paths = {s.paths.output, (c.dir / "surf2.splk").string(), ""};
  EXPECT_EQ(run_splat_convert(o).extra, "");
  const LoadedCloud splk = read_cloud(o.paths.output);
  EXPECT_NE(graph::find_chunk(splk, graph::kSurfaceChunkType), nullptr);
  EXPECT_EQ(splk.cloud.find_extra("surface_id"), nullptr);
  o.paths = {s.paths.output, (c.dir / "surf.las").string(), ""};
  EXPECT_EQ(run_splat_convert(o).extra,
            "las does not keep normals, radii, attribute patch_id, neighbour graph (GRPH), sharp "
            "edges (CLAS), clip partners (CLIP), surface ids (SURF)");

  // A file's own `class` attribute stays; the CLAS chunk is then reported dropped.
  LoadedCloud labelled = doc;
  labelled.cloud.extras.push_back(
      ExtraAttribute("class", ScalarType::kUInt16, std::vector<double>(doc.cloud.size(), 7)));
  const std::string in = (c.dir / "labelled.splk").string();
  write_cloud(labelled, in);
  o.paths = {in, (c.dir / "labelled.ply").string(), ""};
  EXPECT_EQ(run_splat_convert(o).extra,
            "ply does not keep neighbour graph (GRPH), sharp edges (CLAS), clip partners (CLIP)");
  const LoadedCloud kept = read_cloud(o.paths.output);
  ASSERT_NE(kept.cloud.find_extra("class"), nullptr);
  EXPECT_EQ(kept.cloud.find_extra("class")->type(), ScalarType::kUInt16);
  EXPECT_EQ(kept.cloud.find_extra("class")->values[0], 7);
  EXPECT_NE(kept.cloud.find_extra("surface_id"), nullptr);

  // Two SURF chunks, or a malformed one, are refused where they would become attributes; LAS
  // output, which drops them, still converts.
  LoadedCloud twice = doc;
  twice.chunks.push_back(*graph::find_chunk(doc, graph::kSurfaceChunkType));
  write_cloud(twice, in);
  o.paths = {in, (c.dir / "twice.ply").string(), ""};
  expect_stage_error([&] { run_splat_convert(o); }, ErrorKind::kBadInput, "two SURF chunks");
  EXPECT_FALSE(fs::exists(o.paths.output));
  LoadedCloud bad = doc;
  for (RawChunk& chunk : bad.chunks)
    if (std::string_view(chunk.type, 4) == "SURF") chunk.payload.resize(chunk.payload.size() - 4);
  write_cloud(bad, in);
  o.paths = {in, (c.dir / "bad.xyz").string(), ""};
  expect_stage_error([&] { run_splat_convert(o); }, ErrorKind::kBadInput, "labelled.splk: SURF");
  o.paths = {in, (c.dir / "bad.las").string(), ""};
  run_splat_convert(o);
  EXPECT_TRUE(fs::exists(o.paths.output));
}

TEST(AppsSegmentSurfaces, RejectsDuplicateAndCorruptGraphChunks) {
  const CubeGraph c = cube_graph();
  const LoadedCloud good = read_cloud(c.graph);
  SegmentSurfacesOptions o;
  o.paths = {(c.dir / "bad.splk").string(), (c.dir / "o.splk").string(), ""};

  LoadedCloud twice = good;
  twice.chunks.push_back(*graph::find_chunk(good, graph::kGraphChunkType));
  write_cloud(twice, o.paths.input);
  expect_stage_error([&] { run_segment_surfaces(o); }, ErrorKind::kBadInput, "two GRPH chunks");

  LoadedCloud corrupt = good;
  for (RawChunk& chunk : corrupt.chunks)
    if (std::string_view(chunk.type, 4) == "CLIP") chunk.payload.resize(chunk.payload.size() - 1);
  write_cloud(corrupt, o.paths.input);
  expect_stage_error([&] { run_segment_surfaces(o); }, ErrorKind::kBadInput, "bad.splk: CLIP");
  EXPECT_FALSE(fs::exists(o.paths.output));
}

// A 64 x 48 render of `in` to <stem>.png with stats in <stem>.json.
SplatViewOptions small_view(const std::string& in, const std::string& stem) {
  SplatViewOptions o;
  o.input = in;
  o.output = temp_path("view", stem + ".png");
  o.stats_path = temp_path("view", stem + ".json");
  o.width = 64;
  o.height = 48;
  return o;
}

TEST(AppsSplatView, RendersAndRejectsBadNumbers) {
  const std::string in = temp_path("view", "s.ply");
  test::synth("sphere", in, 3000);
  SplatViewOptions o = small_view(in, "s");
  const SplatViewSummary s = run_splat_view(o);
  EXPECT_EQ(s.frames, 1u);
  EXPECT_GT(fs::file_size(o.output), 100u);
  const nlohmann::json stats = read_json(o.stats_path);
  EXPECT_EQ(stats["splats_in"], s.splats);
  EXPECT_GT(stats["pixels_covered"].get<uint64_t>(), 0u);
  EXPECT_EQ(stats["tool"], "splat-view");

  const std::string good = slurp(o.output);
  for (const char* bg : {"nan,0,0", "2,0,0", "-1,0,0", "inf,0,0", "0.5,0.5"}) {
    o.background = bg;
    expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--background");
  }
  o.background = "";
  for (float fov : {0.0f, 180.0f, std::numeric_limits<float>::quiet_NaN()}) {
    o.fov_y_deg = fov;
    expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--fov must be in (0, 180)");
  }
  o.fov_y_deg = 40;
  o.view = "10,20,0";
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--view distance");
  o.view = "";
  o.blend = "zthreshold=inf";
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--blend");
  o.blend = "zthreshold";
  o.eye = "1,nan,1";
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--eye");
  o.eye = "";
  o.stats_path = in;
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage,
                     "--stats must not be the input file");
  EXPECT_EQ(slurp(o.output), good);  // no failed run touched the image
}

// A georeferenced scan (UTM-like coordinates, held in a local frame near the data): --eye,
// --target and the path's points are the file's coordinates.
TEST(AppsSplatView, CamerasAreInTheFileCoordinates) {
  const std::string in = temp_path("view", "utm.splk");
  test::synth("sphere", in, 3000);
  LoadedCloud doc = read_cloud(in);
  doc.cloud.origin = {500000.0, 4000000.0, 100.0};
  write_cloud(doc, in);
  SplatViewOptions o = small_view(in, "utm");
  o.eye = "500003.5,4000002,101";
  o.target = "500000,4000000,100";
  run_splat_view(o);
  const uint64_t covered = read_json(o.stats_path)["pixels_covered"].get<uint64_t>();
  EXPECT_GT(covered, 300u);
  o.eye = "3.5,2,1";  // the local frame is not the file's: the sphere is 4 million units away
  o.target = "0,0,0";
  run_splat_view(o);
  EXPECT_EQ(read_json(o.stats_path)["pixels_covered"].get<uint64_t>(), 0u);
  const std::string path = temp_path("view", "utm-path.json");
  std::ofstream(path) << R"([{"eye": [500003.5, 4000002, 101], "target": [500000, 4000000, 100]}])";
  o.eye = o.target = "";
  o.path = path;
  o.output = temp_path("view", "utm_%02d.png");
  run_splat_view(o);
  EXPECT_EQ(read_json(o.stats_path)["pixels_covered"].get<uint64_t>(), covered);
  // The level-of-detail files keep the local frame's place: .spt in its header, .qs in its
  // comment; their cameras are in file coordinates too.
  BuildQSplatOptions q;
  q.paths = {in, temp_path("view", "utm.qs"), ""};
  run_build_qsplat(q);
  BuildSptOptions t;
  t.paths = {in, temp_path("view", "utm.spt"), ""};
  run_build_spt(t);
  for (const std::string& lod : {q.paths.output, t.paths.output}) {
    SplatViewOptions v = small_view(lod, "utm-lod");
    v.eye = "500003.5,4000002,101";
    v.target = "500000,4000000,100";
    run_splat_view(v);
    EXPECT_GT(read_json(v.stats_path)["pixels_covered"].get<uint64_t>(), covered / 2) << lod;
  }
}

// Every frame's name is checked before the first frame is written: a frame that cannot be
// written fails the run with the earlier frames untouched.
TEST(AppsSplatView, AFrameThatCannotBeWrittenFailsBeforeAnyIs) {
  const std::string in = temp_path("view", "tt.ply");
  test::synth("sphere", in, 500);
  SplatViewOptions o;
  o.input = in;
  o.output = temp_path("view", "tt/f_%04d.png");
  o.turntable = 3;
  o.width = 32;
  o.height = 24;
  fs::create_directories(temp_path("view", "tt/f_0001.png"));
  std::ofstream(temp_path("view", "tt/f_0000.png")) << "old";
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kOutput, "is a directory");
  EXPECT_EQ(slurp(temp_path("view", "tt/f_0000.png")), "old");
}

TEST(AppsSplatView, TurntableFrameNames) {
  EXPECT_EQ(frame_path("out/turn_%04d.png", 7), "out/turn_0007.png");
  EXPECT_EQ(frame_path("f%d.exr", 12), "f12.exr");
  EXPECT_EQ(frame_path("50%%/f%3d_%%.png", 7), "50%/f  7_%.png");  // printf's %%
  EXPECT_EQ(frame_path("no_number.png", 3), "no_number.png");
  SplatViewOptions o;
  o.input = temp_path("view", "unused.ply");
  o.output = temp_path("view", "no_number.png");
  o.turntable = 4;
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--turntable needs");
  for (const char* bad : {"f_%04d_%d.png", "f_%s%04d.png", "f_%04d%.png", "f_%010d.png"}) {
    o.output = temp_path("view", bad);
    expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "--turntable needs");
  }
  o.output = temp_path("view", "x.png");
  o.turntable = 0;
  o.eye = "1,1,1";
  o.view = "0,0";
  expect_stage_error([&] { run_splat_view(o); }, ErrorKind::kUsage, "alternatives");
}

TEST(AppsSplatInfo, DescribesTheGoodFilesAndReportsTheBadOne) {
  const std::string a = temp_path("info", "a.ply"), b = temp_path("info", "b.ply");
  const std::string bad = temp_path("info", "bad.ply");
  test::synth("sphere", a, 100);
  test::synth("cube", b, 200);
  std::ofstream(bad) << "ply\nformat binary_little_endian 1.0\nelement vertex 5\n";
  SplatInfoOptions o;
  o.files = {a, bad, b};
  o.json = true;
  std::ostringstream out, err;
  expect_stage_error([&] { run_splat_info(o, out, err); }, ErrorKind::kBadInput,
                     "1 of 3 files could not be described");
  const nlohmann::json j = nlohmann::json::parse(out.str());
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["points"], read_cloud(a).cloud.size());
  EXPECT_EQ(j[1]["points"], read_cloud(b).cloud.size());
  EXPECT_NE(err.str().find("bad.ply"), std::string::npos) << err.str();
  // One bad file alone: its own error.
  o.files = {bad};
  std::ostringstream out1, err1;
  expect_stage_error([&] { run_splat_info(o, out1, err1); }, ErrorKind::kBadInput, "bad.ply");
}

}  // namespace
}  // namespace splatkit::apps
