// check_tile_halo: a tile's own points near a side the survey goes on past are checked against
// the halo; a halo narrower than their neighbourhoods reach is found, with the halo that would do.
#include "apps/check_tile_halo.h"

#include <gtest/gtest.h>

#include <string>

namespace splatkit::apps {
namespace {

// A 0.1-spaced grid on z = 0 over x in [-halo, 10), y in [0, 10) (file coordinates, origin
// (1000, 2000, 0)), points with x < 0 marked as halo; the tile's square is [0, 10]^2.
SplatCloud grid_tile(double halo) {
  SplatCloud cloud;
  cloud.origin = {1000, 2000, 0};
  std::vector<double> flags;
  for (int i = -static_cast<int>(halo * 10 + 0.5); i < 100; ++i)
    for (int j = 0; j < 100; ++j) {
      cloud.positions.push_back({0.1f * static_cast<float>(i) + 0.05f,
                                 0.1f * static_cast<float>(j) + 0.05f, 0});
      flags.push_back(i < 0 ? 1 : 0);
    }
  cloud.extras.emplace_back("halo", ScalarType::kUInt8, flags);
  return cloud;
}

nlohmann::json tile_metadata(double halo, const std::string& minus_x) {
  return nlohmann::json::parse(
      R"({"tile": {"i": 100, "j": 200, "square": {"min": [1000, 2000], "max": [1010, 2010]},
          "halo": )" +
      std::to_string(halo) + R"(, "skyline": {"band": 5, "-x": )" + minus_x +
      R"(, "+x": [null], "-y": [null], "+y": [null]}}})");
}

TEST(CheckTileHalo, AWideHaloHoldsEveryNeighbourhood) {
  // The 64th nearest on a 0.1 grid lies ~0.45 away, its points' 32nd ~0.32: ~0.77 past the cut.
  const TileHaloCheck c = check_tile_halo(tile_metadata(1.2, "[3.0]"), grid_tile(1.2));
  ASSERT_TRUE(c.tile);
  EXPECT_EQ(c.checked, 12u * 100u);  // the own points within one halo of the -x side
  EXPECT_EQ(c.short_of, 0u);
  EXPECT_EQ(c.needed, 0);
}

TEST(CheckTileHalo, ANarrowHaloIsFoundWithTheHaloThatWouldDo) {
  const TileHaloCheck c = check_tile_halo(tile_metadata(0.3, "[3.0]"), grid_tile(0.3));
  ASSERT_TRUE(c.tile);
  EXPECT_EQ(c.checked, 3u * 100u);
  EXPECT_EQ(c.short_of, c.checked);
  // On the whole grid a cut point's 64 nearest reach ~0.45 past the cut and their own 32 nearest
  // ~0.77 (a point ~0.45 out, with its 32nd ~0.32 away); the points the narrow halo lacks only
  // push those farther: at least that, never far more.
  EXPECT_GT(c.needed, 0.75);
  EXPECT_LT(c.needed, 1.2);
  const nlohmann::json j = c.to_json();
  EXPECT_EQ(j.at("points_short").get<std::size_t>(), c.short_of);
  EXPECT_DOUBLE_EQ(j.at("halo").get<double>(), 0.3);
}

TEST(CheckTileHalo, SidesWhereTheSurveyEndsAreNotChecked) {
  const TileHaloCheck c = check_tile_halo(tile_metadata(0.3, "[null, null]"), grid_tile(0.3));
  EXPECT_TRUE(c.tile);
  EXPECT_EQ(c.checked, 0u);
  EXPECT_EQ(c.short_of, 0u);
}

TEST(CheckTileHalo, NothingWithoutATile) {
  const TileHaloCheck c = check_tile_halo(nlohmann::json::object(), grid_tile(0.3));
  EXPECT_FALSE(c.tile);
  EXPECT_TRUE(c.to_json().is_null());
  EXPECT_FALSE(check_tile_halo(nlohmann::json::parse(R"({"tile": {"halo": "wide"}})"),
                               grid_tile(0.3))
                   .tile);
}

}  // namespace
}  // namespace splatkit::apps
