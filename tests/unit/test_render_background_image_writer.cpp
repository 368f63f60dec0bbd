// BackgroundImageWriter: the files hold the bytes write_image() gives (PNG and EXR), files are
// committed only when asked, and a failing image leaves no temporary file and throws its error
// from wait(); dropping an image in flight removes its uncommitted file.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "render/background_image_writer.h"
#include "render/write_image.h"
#include "splatkit/error.h"
#include "test_format_support.h"

namespace splatkit::render {
namespace {

namespace fs = std::filesystem;

Framebuffer gradient(const std::string& path) {
  Framebuffer f;
  f.allocate(40, 30, planes_for_output(path));
  for (std::size_t i = 0; i < f.rgb8.size(); ++i) f.rgb8[i] = uint8_t(i * 7 % 251);
  for (std::size_t i = 0; i < f.rgba.size(); ++i) f.rgba[i] = 0.001f * float(i % 997);
  for (std::size_t i = 0; i < f.depth.size(); ++i) f.depth[i] = 1.0f + 0.01f * float(i);
  for (std::size_t i = 0; i < f.normal.size(); i += 3) f.normal[i + 2] = 1;
  return f;
}

std::size_t files_in(const fs::path& dir) {
  return std::distance(fs::directory_iterator(dir), fs::directory_iterator());
}

TEST(RenderBackgroundImageWriter, WritesTheBytesOfWriteImage) {
  for (const char* name : {"frame.png", "frame.exr"}) {
    const std::string expected = test::temp_path("bgwriter", std::string("ref_") + name);
    const std::string path = test::temp_path("bgwriter", name);
    write_image(gradient(name), expected);
    BackgroundImageWriter writer;
    EXPECT_FALSE(writer.busy());
    writer.start(gradient(name), path, true);
    EXPECT_TRUE(writer.busy());
    BackgroundImageWriter::Written done = writer.wait();
    EXPECT_FALSE(writer.busy());
    EXPECT_EQ(test::slurp(path), test::slurp(expected)) << name;
    EXPECT_EQ(done.frame.width, 40);  // handed back for reuse
    EXPECT_GE(done.seconds, 0);
  }
}

TEST(RenderBackgroundImageWriter, CommitsOnlyWhenAsked) {
  const std::string path = test::temp_path("bgwriter", "last.png");
  BackgroundImageWriter writer;
  writer.start(gradient(path), path, false);
  BackgroundImageWriter::Written done = writer.wait();
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(files_in(fs::path(path).parent_path()), 1u);  // the temporary file
  done.file->commit();
  EXPECT_TRUE(fs::exists(path));

  // Dropped uncommitted, in flight or after wait(): nothing stays.
  const std::string other = test::temp_path("bgwriter", "dropped.png");
  {
    BackgroundImageWriter w;
    w.start(gradient(other), other, false);
  }
  {
    BackgroundImageWriter w;
    w.start(gradient(other), other, false);
    w.wait();
  }
  EXPECT_FALSE(fs::exists(other));
  EXPECT_EQ(files_in(fs::path(path).parent_path()), 1u);
}

TEST(RenderBackgroundImageWriter, FailuresComeBackFromWaitAndLeaveNoFile) {
  const std::string dir = fs::path(test::temp_path("bgwriter", "x")).parent_path().string();
  BackgroundImageWriter writer;
  // Created, then refused by the encoder: the temporary file goes.
  writer.start(gradient("x.png"), dir + "/frame.nosuchformat", true);
  try {
    writer.wait();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kUsage);
  }
  EXPECT_EQ(files_in(dir), 0u);
  // Not creatable: the output error, and the writer is usable again.
  writer.start(gradient("x.png"), dir + "/no/such/dir/frame.png", true);
  try {
    writer.wait();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::kOutput);
  }
  EXPECT_FALSE(writer.busy());
  EXPECT_THROW(writer.wait(), std::logic_error);
  writer.start(gradient("x.png"), dir + "/ok.png", true);
  EXPECT_THROW(writer.start(gradient("x.png"), dir + "/ok2.png", true), std::logic_error);
  writer.wait();
  EXPECT_EQ(files_in(dir), 1u);
}

}  // namespace
}  // namespace splatkit::render
