// shade_row against shade_pixel, pixel by pixel: the same bits in every shading mode, for random
// normals (some facing away, some not unit, one zero), albedos and depths, on runs of every length
// at the image's edges and centre.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "render/shade_row.h"
#include "splatkit/deterministic_rng.h"

namespace splatkit::render {
namespace {

bool same_bits(const Vec3f& a, const Vec3f& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(RenderShadeRow, SameBitsAsShadePixel) {
  Camera camera;
  camera.eye = {0.3f, -4, 1.2f};
  camera.width = 97;
  camera.height = 61;
  const Projection pr = make_projection(camera);
  DeterministicRng rng(7);
  auto uniform = [&](float lo, float hi) { return static_cast<float>(rng.uniform(lo, hi)); };
  for (ShadeMode mode :
       {ShadeMode::kPhong, ShadeMode::kNormals, ShadeMode::kDepth, ShadeMode::kFlat}) {
    const Shading shading = make_shading(mode, pr, {{0, 0, 0}, 1.5f});
    for (int y : {0, 30, 60}) {
      for (int x0 : {0, 40, 65}) {
        for (int count = 1; count <= kMaxShadeRun; ++count) {
          std::vector<PixelSurface> g(count);
          for (PixelSurface& s : g) {
            s.normal = {uniform(-2, 2), uniform(-2, 2), uniform(-2, 2)};
            s.albedo = {uniform(0, 1), uniform(0, 1), uniform(0, 1)};
            s.depth = uniform(2, 6);
            s.alpha = 1;
          }
          if (count == 5) g[2].normal = {0, 0, 0};
          Vec3f colors[kMaxShadeRun];
          shade_row(shading, pr, x0, y, count, g.data(), colors);
          for (int i = 0; i < count; ++i) {
            const Vec3f view = -normalized(pr.ray(x0 + i + 0.5f, y + 0.5f));
            const Vec3f want = shade_pixel(shading, g[i].normal, view, g[i].albedo, g[i].depth);
            ASSERT_TRUE(same_bits(colors[i], want))
                << "mode " << int(mode) << " pixel " << x0 + i << "," << y << ": " << colors[i].x
                << " " << colors[i].y << " " << colors[i].z << " against " << want.x << " "
                << want.y << " " << want.z;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace splatkit::render
