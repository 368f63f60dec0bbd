// The GeoTIFF tag reader on real and hand-made headers: no-data and georeferencing from classic
// little-endian and BigTIFF big-endian files; malformed headers (truncated, offsets past the end,
// absurd counts, wrong types) are errors naming the file, read in time linear in the header.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <vector>

#include "splatkit/error.h"
#include "terrain/tiff_geo_tags.h"

namespace splatkit::terrain {
namespace {

std::vector<uint8_t> seed(const std::string& name) {
  std::ifstream in(std::string(SPLATKIT_SOURCE_DIR) + "/tests/fuzz/corpus/tiff_geo_tags/" + name,
                   std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TiffGeoTags read(const std::vector<uint8_t>& d) {
  return read_tiff_geo_tags_memory(d.data(), d.size(), "x.tif");
}

TEST(TerrainTiffGeoTags, ClassicSrtmCrop) {
  const TiffGeoTags t = read(seed("fuji-16.tif"));
  ASSERT_TRUE(t.nodata.has_value());
  EXPECT_EQ(*t.nodata, -32768);
  EXPECT_EQ(t.georef["crs"], "EPSG:4326");
  EXPECT_EQ(t.georef["raster_type"], "area");
  EXPECT_NEAR(t.georef["pixel_scale"][0].get<double>(), 1.0 / 1200, 1e-12);
  EXPECT_EQ(t.georef["tiepoint"].size(), 6u);
}

TEST(TerrainTiffGeoTags, BigTiffBigEndian) {
  const TiffGeoTags t = read(seed("bigtiff-be.tif"));
  ASSERT_TRUE(t.nodata.has_value());
  EXPECT_EQ(*t.nodata, -9999);
  EXPECT_EQ(t.georef["pixel_scale"][0], 0.5);
}

TEST(TerrainTiffGeoTags, MalformedHeadersAreErrors) {
  EXPECT_THROW(read(seed("truncated.tif")), Error);
  EXPECT_THROW(read({}), Error);
  EXPECT_THROW(read({'I', 'I', 42, 0}), Error);
  EXPECT_THROW(read({'X', 'X', 42, 0, 8, 0, 0, 0}), Error);
  EXPECT_THROW(read({'I', 'I', 41, 0, 8, 0, 0, 0}), Error);
  EXPECT_THROW(read({'I', 'I', 42, 0, 0xff, 0xff, 0xff, 0xff}), Error);  // directory past the end
  // A directory claiming 65535 entries in a 10-byte file.
  EXPECT_THROW(read({'I', 'I', 42, 0, 8, 0, 0, 0, 0xff, 0xff}), Error);
  // GDAL_NODATA as a number instead of ASCII, and a value offset past the end.
  std::vector<uint8_t> d = {'I', 'I', 42, 0, 8, 0, 0, 0, 1, 0,
                            0x81, 0xa4, 3, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_THROW(read(d), Error);
  d[12] = 2;               // ASCII, 40 bytes at offset 1000
  d[14] = 40;
  d[18] = 0xe8;
  d[19] = 0x03;
  try {
    read(d);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.tif: TIFF: tag 42113 values run past the end"),
              std::string::npos)
        << e.what();
  }
  // No tags of interest: no no-data, no georeferencing.
  const TiffGeoTags none = read({'I', 'I', 42, 0, 8, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_FALSE(none.nodata.has_value());
  EXPECT_TRUE(none.georef.is_null());
}

}  // namespace
}  // namespace splatkit::terrain
