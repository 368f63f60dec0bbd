// tile_survey_box: splat-tile's survey box, from the tile's metadata or its history, in the
// cloud's frame; a box that is malformed or does not hold the tile's points gives none; and the
// Morton grid of --morton-grid has the cube's cell sides.
#include "apps/tile_survey_box.h"

#include <gtest/gtest.h>

#include "apps/morton_tile_grid.h"

namespace splatkit::apps {
namespace {

const Bounds kOwn{{1, 2, 3}, {4, 5, 6}};

TEST(TileSurveyBox, FromTheTileOrItsNewestHistoryEntry) {
  const auto box = R"({"min": [1000.5, 2000, 0], "max": [1010, 2010.25, 9]})"_json;
  const std::array<double, 3> origin{1000, 2000, -1};
  const auto in_tile = tile_survey_box({{"tile", {{"survey_box", box}}}}, origin, kOwn);
  ASSERT_TRUE(in_tile.has_value());
  EXPECT_EQ(in_tile->min, (Vec3f{0.5f, 0, 1}));
  EXPECT_EQ(in_tile->max, (Vec3f{10, 10.25f, 10}));
  const nlohmann::json older = {
      {"tile", {{"survey_box", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}}}}};
  const nlohmann::json history = {{"tool", "estimate-normals"},
                                  {"history", {older, {{"tile", {{"survey_box", box}}}}}}};
  const auto from_history = tile_survey_box(history, origin, kOwn);
  ASSERT_TRUE(from_history.has_value());
  EXPECT_EQ(from_history->min, in_tile->min);
}

TEST(TileSurveyBox, NoneWhenMalformedOrNotHoldingTheTile) {
  const std::array<double, 3> origin{0, 0, 0};
  EXPECT_FALSE(tile_survey_box(nlohmann::json::object(), origin, kOwn));
  EXPECT_FALSE(tile_survey_box({{"tile", {{"i", 1}}}}, origin, kOwn));
  for (const char* bad :
       {R"({"min": [0, 0], "max": [9, 9, 9]})", R"({"min": [0, 0, "a"], "max": [9, 9, 9]})",
        R"({"min": [0, 0, 9], "max": [9, 9, 0]})", R"({"min": [0, 0, 0], "max": [9, 9, 1e300]})",
        R"({"min": [2, 0, 0], "max": [9, 9, 9]})", R"({"min": [0, 0, 0], "max": [9, 4.5, 9]})"})
    EXPECT_FALSE(
        tile_survey_box({{"tile", {{"survey_box", nlohmann::json::parse(bad)}}}}, origin, kOwn))
        << bad;
}

TEST(MortonTileGrid, TheLargestCellSideAtMostTheSizeAnchoredAtTheCorner) {
  // extent 100 (y): cells of 100 · 2^21 / (2^21 − 1) / 2^k.
  const TileGridFrame g = morton_tile_grid({-10, 5, 0}, {30, 105, 20}, 30);
  EXPECT_EQ(g.x0, -10);
  EXPECT_EQ(g.y0, 5);
  EXPECT_DOUBLE_EQ(g.size, 100.0 / 2097151.0 * 2097152.0 / 4);
  EXPECT_EQ(morton_tile_grid({1, 1, 1}, {1, 1, 1}, 7).size, 7);
}

}  // namespace
}  // namespace splatkit::apps
