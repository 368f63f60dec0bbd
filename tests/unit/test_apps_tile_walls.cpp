// tile_walls: splat-tile's skyline becomes walls on the halo's outer edge, in the cloud's frame;
// metadata that does not read as a tile's gives none.
#include "apps/tile_walls.h"

#include <gtest/gtest.h>

namespace splatkit::apps {
namespace {

TEST(TileWalls, OneWallPerSegmentTheSurveyReachesBeyond) {
  SplatCloud cloud;
  cloud.origin = {1000, 2000, 0};
  cloud.positions = {{5, 5, 2}, {15, 15, 9}};
  const nlohmann::json meta = nlohmann::json::parse(R"({"tile": {"i": 100, "j": 200,
      "square": {"min": [1000, 2000], "max": [1020, 2020]}, "halo": 2,
      "skyline": {"band": 10, "-x": [null, 12.5], "+x": [1.0, null], "+y": [30, 30]}}})");
  const std::vector<VisibilityWall> walls = tile_walls(meta, cloud);
  // -x: its second segment; +x: 1.0 is below the lowest point (2): none; +y: both; -y: none.
  ASSERT_EQ(walls.size(), 3u);
  EXPECT_EQ(walls[0].base, (Vec3f{-2, 10, 2}));  // x = 1000 - 2 - origin, y from -2 + 24 / 2
  EXPECT_EQ(walls[0].along, (Vec3f{0, 12, 0}));
  EXPECT_EQ(walls[0].top, 12.5f);
  EXPECT_EQ(walls[1].base, (Vec3f{-2, 22, 2}));
  EXPECT_EQ(walls[2].base, (Vec3f{10, 22, 2}));
  EXPECT_EQ(walls[2].top, 30.0f);
}

TEST(TileWalls, NoneWithoutATile) {
  SplatCloud cloud;
  cloud.positions = {{0, 0, 0}};
  EXPECT_TRUE(tile_walls(nlohmann::json::object(), cloud).empty());
  EXPECT_TRUE(tile_walls(nlohmann::json::parse(R"({"tile": {"square": 3}})"), cloud).empty());
  EXPECT_TRUE(tile_walls(nlohmann::json::parse(R"({"tile": {"i": 0, "j": 0, "halo": -1,
      "square": {"min": [0, 0], "max": [1, 1]}, "skyline": {"-x": [5]}}})"),
                         cloud)
                  .empty());
  EXPECT_TRUE(tile_walls(nlohmann::json::parse(R"({"tile": {"i": 0, "j": 0, "halo": 1,
      "square": {"min": [0, 0], "max": [1, 1]}, "skyline": {"-x": "high"}}})"),
                         cloud)
                  .empty());
}

}  // namespace
}  // namespace splatkit::apps
