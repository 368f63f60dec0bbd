// Stage (lib/apps/stage.h), same_file and check_splats: the checks every stage makes before work.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "apps/stage.h"
#include "splatkit/check_splats.h"
#include "splatkit/same_file.h"
#include "test_apps_support.h"

namespace splatkit::apps {
namespace {

namespace fs = std::filesystem;
using test::expect_stage_error;
using test::temp_path;

void touch(const std::string& path) { std::ofstream(path) << "x"; }

TEST(AppsSameFile, SpellingsOfOneExistingFile) {
  const std::string m = temp_path("same", "m.ply");
  touch(m);
  const fs::path dir = fs::path(m).parent_path();
  fs::create_symlink(m, dir / "link.ply");
  fs::create_hard_link(m, dir / "hard.ply");
  touch((dir / "other.ply").string());
  EXPECT_TRUE(same_file(m, m));
  EXPECT_TRUE(same_file(m, (dir / "." / "m.ply").string()));
  fs::create_directory(dir / "sub");
  EXPECT_TRUE(same_file(m, (dir / "sub" / ".." / "m.ply").string()));
  EXPECT_TRUE(same_file(m, (dir / "link.ply").string()));
  EXPECT_TRUE(same_file(m, (dir / "hard.ply").string()));
  EXPECT_FALSE(same_file(m, (dir / "other.ply").string()));
  EXPECT_FALSE(same_file(m, (dir / "missing.ply").string()));
}

TEST(AppsSameFile, FilesNotYetCreated) {
  const fs::path dir = fs::path(temp_path("same", "x")).parent_path();
  const std::string a = (dir / "new.json").string();
  EXPECT_TRUE(same_file(a, (dir / "." / "new.json").string()));
  fs::create_symlink(dir / "new.json", dir / "dangling.json");  // writing it creates new.json
  EXPECT_TRUE(same_file(a, (dir / "dangling.json").string()));
  EXPECT_FALSE(same_file(a, (dir / "new2.json").string()));
  // A relative spelling of the same new file.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  EXPECT_TRUE(same_file("new.json", a));
  EXPECT_TRUE(same_file("./new.json", a));
  fs::current_path(cwd);
}

TEST(AppsSameFile, DevicesAreNeverTheSameFile) {
  EXPECT_FALSE(same_file("/dev/null", "/dev/null"));
}

TEST(AppsStage, RejectsReportOrOutputNamingTheInputInAnySpelling) {
  const std::string in = temp_path("stage", "m.ply");
  test::synth("sphere", in, 200);
  const fs::path dir = fs::path(in).parent_path();
  fs::create_symlink(in, dir / "alias.ply");
  fs::create_hard_link(in, dir / "hard.ply");
  const std::string out = (dir / "o.splk").string();
  for (const std::string& spelling :
       std::vector<std::string>{in, (dir / "." / "m.ply").string(), (dir / "alias.ply").string(),
                                (dir / "hard.ply").string()}) {
    expect_stage_error(
        [&] {
          Stage("t", {in, out, spelling});
        },
        ErrorKind::kUsage, "--report must not be the input file");
    expect_stage_error(
        [&] {
          Stage("t", {in, spelling, ""});
        },
        ErrorKind::kUsage, "an input is never overwritten");
  }
  expect_stage_error(
      [&] {
        Stage("t", {in, out, (dir / "." / "o.splk").string()}, "--stats");
      },
      ErrorKind::kUsage, "--stats must not be OUT");
  expect_stage_error(
      [&] {
        Stage("t", {in, "-", "-"});
      },
      ErrorKind::kUsage, "--report must not be OUT");
  EXPECT_NO_THROW(Stage("t", {in, out, (dir / "r.json").string()}));
}

TEST(AppsStage, ChecksOutputsBeforeAnyWork) {
  const std::string in = temp_path("stage", "m.ply");
  test::synth("sphere", in, 200);
  const fs::path dir = fs::path(in).parent_path();
  expect_stage_error(
      [&] {
        Stage("t", {in, (dir / "no/such/o.splk").string(), ""});
      },
      ErrorKind::kOutput, "o.splk: cannot create");
  expect_stage_error(
      [&] {
        Stage("t", {in, (dir / "o.splk").string(), (dir / "no/such/r.json").string()});
      },
      ErrorKind::kOutput, "r.json: cannot create");
  expect_stage_error(
      [&] {
        Stage("t", {in, dir.string(), ""});
      },
      ErrorKind::kOutput, "is a directory");
}

TEST(AppsStage, NamesTheStepWhenMemoryRunsOutAndTheFileInBadInput) {
  const std::string in = temp_path("stage", "m.ply");
  test::synth("sphere", in, 200);
  Stage stage("t", {in, "-", ""});
  expect_stage_error(
      [&] { stage.phase("x", "building the graph", []() -> int { throw std::bad_alloc(); }); },
      ErrorKind::kOutOfMemory, "out of memory while building the graph");
  expect_stage_error(
      [&] {
        stage.phase("x", "indexing",
                    []() -> int { throw Error(ErrorKind::kBadInput, "point 1 is odd"); });
      },
      ErrorKind::kBadInput, in + ": point 1 is odd");
}

SplatCloud splats(std::size_t n) {
  SplatCloud c;
  for (std::size_t i = 0; i < n; ++i) {
    c.positions.push_back({float(i), 0, 0});
    c.normals.push_back({0, 0, 2});  // any length: consumers normalise
    c.radii.push_back(0.5f);
  }
  return c;
}

TEST(AppsCheckSplats, OneMessagePerFaultNamingFileAndSplat) {
  EXPECT_NO_THROW(check_splats(splats(20), "s.ply"));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct Case {
    Vec3f normal;
    float radius;
    const char* message;
  } cases[] = {
      {{0, 0, 0}, 1, "s.ply: splat 17: normal is zero"},
      {{nan, 0, 1}, 1, "s.ply: splat 17: normal is not finite"},
      {{0, inf, 1}, 1, "s.ply: splat 17: normal is not finite"},
      {{1e-30f, 0, 0}, 1, "s.ply: splat 17: normal cannot be normalised"},
      {{0, 0, 1}, -1, "s.ply: splat 17: radius -1 is negative"},
      {{0, 0, 1}, inf, "s.ply: splat 17: radius inf is not finite"},
      {{0, 0, 1}, nan, "s.ply: splat 17: radius nan is not finite"},
      {{0, 0, 1}, 0, "s.ply: splat 17: radius is zero"},
  };
  for (const Case& c : cases) {
    SplatCloud cloud = splats(20);
    cloud.normals[17] = c.normal;
    cloud.radii[17] = c.radius;
    cloud.radii[19] = -5;  // a later fault: the lowest index is reported
    expect_stage_error([&] { check_splats(cloud, "s.ply"); }, ErrorKind::kBadInput, c.message);
  }
  struct EllipseCase {
    Vec3f axis;
    float minor;
    const char* message;
  } ellipse_cases[] = {
      {{1, 0, 0}, 0.25f, nullptr},
      {{2, 0, 0}, 0.25f, "s.ply: splat 17: ellipse axis is not a unit vector"},
      {{0.6f, 0, 0.8f}, 0.25f, "s.ply: splat 17: ellipse axis is not in the splat's plane"},
      {{nan, 0, 0}, 0.25f, "s.ply: splat 17: ellipse axis is not finite"},
      {{0, 1, 0}, 0, "s.ply: splat 17: minor radius 0 is not positive"},
      {{0, 1, 0}, 0.75f, "s.ply: splat 17: minor radius 0.75 exceeds the radius 0.5"},
  };
  for (const EllipseCase& c : ellipse_cases) {
    SplatCloud cloud = splats(20);
    cloud.axes.assign(20, Vec3f{1, 0, 0});
    cloud.minor_radii.assign(20, 0.5f);
    cloud.axes[17] = c.axis;
    cloud.minor_radii[17] = c.minor;
    if (c.message == nullptr)
      EXPECT_NO_THROW(check_splats(cloud, "s.ply"));
    else
      expect_stage_error([&] { check_splats(cloud, "s.ply"); }, ErrorKind::kBadInput, c.message);
  }
  // Over many chunks checked in parallel, still the lowest bad index.
  SplatCloud many = splats(300000);
  many.radii[290000] = 0;
  many.radii[70001] = -2;
  many.normals[200000] = {0, 0, 0};
  expect_stage_error([&] { check_splats(many, "s.ply"); }, ErrorKind::kBadInput,
                     "s.ply: splat 70001: radius -2 is negative");
  SplatCloud bare = splats(3);
  bare.radii.clear();
  expect_stage_error([&] { check_splats(bare, "s.ply"); }, ErrorKind::kBadInput,
                     "s.ply: the cloud has no radii; run estimate-normals first");
}

}  // namespace
}  // namespace splatkit::apps
