// write_image's EXR: the surface_id channel is a 32-bit unsigned integer channel holding the
// frame's ids exactly (read back with OpenImageIO), next to the float channels; without ids the
// file has the eight float channels only. PNG (written with fast settings) is lossless.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <unistd.h>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "render/framebuffer.h"
#include "render/write_image.h"

namespace splatkit::render {
namespace {

std::string temp_path(const std::string& name) {
  return ::testing::TempDir() + "render_write_image_" + std::to_string(::getpid()) + "_" + name;
}

Framebuffer small_frame(bool ids) {
  Framebuffer f;
  FramebufferPlanes p = planes_for_output("x.exr", ids);
  f.allocate(3, 2, p);
  for (std::size_t i = 0; i < 6; ++i) {
    for (int c = 0; c < 4; ++c) f.rgba[4 * i + c] = 0.25f * c + 0.01f * i;
    f.depth[i] = 1.5f + i;
    f.normal[3 * i + 2] = 1;
    f.alpha[i] = 1;
    if (ids) f.surface_id[i] = i == 5 ? kNoSurfaceId : uint32_t(16777217u * i);
  }
  return f;
}

TEST(RenderWriteImage, ExrSurfaceIdChannelIsExactUnsigned) {
  const Framebuffer f = small_frame(true);
  ASSERT_EQ(f.surface_id.size(), 6u);
  const std::string path = temp_path("ids.exr");
  write_image(f, path);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  ASSERT_EQ(spec.nchannels, 9);
  const int id_channel = spec.channelindex("surface_id");
  ASSERT_GE(id_channel, 0);
  EXPECT_EQ(spec.channelformat(id_channel), OIIO::TypeDesc::UINT32);
  EXPECT_EQ(spec.channelformat(spec.channelindex("Z")), OIIO::TypeDesc::FLOAT);
  std::vector<uint32_t> ids(6);
  ASSERT_TRUE(in->read_image(0, 0, id_channel, id_channel + 1, OIIO::TypeDesc::UINT32, ids.data()));
  EXPECT_EQ(ids, f.surface_id);  // 16777217·i is not a float: exact only as an integer
  std::vector<float> z(6);
  const int zc = spec.channelindex("Z");
  ASSERT_TRUE(in->read_image(0, 0, zc, zc + 1, OIIO::TypeDesc::FLOAT, z.data()));
  EXPECT_EQ(z, f.depth);
  in->close();
  std::remove(path.c_str());
}

TEST(RenderWriteImage, ExrWithoutIdsHasEightFloatChannels) {
  const std::string path = temp_path("noids.exr");
  write_image(small_frame(false), path);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 8);
  EXPECT_LT(in->spec().channelindex("surface_id"), 0);
  in->close();
  std::remove(path.c_str());
}

TEST(RenderWriteImage, PngIsLossless) {
  // The fast settings (Up filter, run-length strategy) on a frame with flat runs and noise.
  Framebuffer f;
  f.allocate(67, 41, planes_for_output("x.png"));
  for (std::size_t i = 0; i < f.rgb8.size(); ++i)
    f.rgb8[i] = i < f.rgb8.size() / 2 ? 40 : uint8_t((i * 2654435761u) >> 24);
  const std::string path = temp_path("lossless.png");
  write_image(f, path);
  auto in = OIIO::ImageInput::open(path);
  ASSERT_TRUE(in);
  ASSERT_EQ(in->spec().nchannels, 3);
  std::vector<uint8_t> back(f.rgb8.size());
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, back.data()));
  EXPECT_EQ(back, f.rgb8);
  in->close();
  std::remove(path.c_str());
}

TEST(RenderWriteImage, PngNeverAsksForIds) {
  EXPECT_FALSE(planes_for_output("x.png", true).surface_ids);
  EXPECT_TRUE(planes_for_output("x.exr", true).surface_ids);
  EXPECT_FALSE(planes_for_output("x.exr", false).surface_ids);
}

}  // namespace
}  // namespace splatkit::render
