// libFuzzer target for the GeoTIFF tag reader (no-data and georeferencing tags of the first
// directory): any input must either give tags with a JSON-serialisable georeferencing or throw
// splatkit::Error; anything else (crash, other exception, sanitizer report) is a bug.
#include <cstddef>
#include <cstdint>

#include "splatkit/error.h"
#include "terrain/tiff_geo_tags.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const splatkit::terrain::TiffGeoTags tags =
        splatkit::terrain::read_tiff_geo_tags_memory(data, size, "fuzz.tif");
    (void)tags.georef.dump();
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
