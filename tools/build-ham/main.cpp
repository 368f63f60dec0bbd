// build-ham: declares the options of apps::run_build_ham (lib/apps) and calls it.
#include "apps/run_build_ham.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "build-ham",
      "Compute the height acceleration map (HAM) of a heightmap for terrain tessellation "
      "[Sobel68; Valdetaro10]: the Sobel gradient magnitude of the heights, then the Sobel "
      "magnitude "
      "of that (clamp-to-edge borders), summarised per tile as an EXR with the float channels "
      "ham_max, h_max and the uint32 channels x, y (texel of h_max, first in row-major order) and "
      "voids (no-data texels filled). IN: TIFF/GeoTIFF (8/16/32-bit integer or float, stripped "
      "or tiled), PNG (8/16-bit), EXR, SRTM .hgt, or headerless RAW with --raw. No-data comes from "
      "the file (GDAL_NODATA tag, SRTM's -32768), --nodata, and NaN; voids are filled from the "
      "nearest good samples along rows and columns, then smoothed, before differentiating, and "
      "the HAM of texels within 2 of a filled sample is bounded by the largest HAM of the valid "
      "terrain within 32 texels (formats/ham.md), so voids never become cliffs or spikes. The "
      "map is streamed in "
      "bands of rows: memory does not grow with its height.",
      "  $ build-ham N46W122.hgt rainier-tiles.exr --report ham.json\n"
      "  $ build-ham dem.tif tiles.exr --tile 32 --ham-full ham.exr --z-scale 2\n"
      "  $ cat dem.f32 | build-ham - dem-f32.exr --raw 1024,1024,float32,little\n");
  splatkit::apps::BuildHamOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Heightmap ('-' = stdin, with --raw only)",
                  "Per-tile HAM, .exr ('-' = stdout)");
  app.add_option("--tile", o.tile, "Tile side in texels (the last row and column may be partial)")
      ->default_val(64)
      ->check(CLI::Range(1, 65536));
  app.add_option("--ham-full", o.ham_full,
                 "Also write the full-resolution HAM as a tiled float EXR (channel 'ham')");
  app.add_option("--nodata", o.nodata,
                 "No-data value (overrides the file's own; NaN is always a void)");
  app.add_option("--z-scale", o.z_scale, "Multiply heights by S before anything else")
      ->default_val(1.0)
      ->check(splatkit::positive_finite());
  app.add_option("--raw", o.raw,
                 "IN is headerless RAW: width, height, sample type (int8 uint8 int16 uint16 "
                 "int32 uint32 float32 float64), byte order (little, default, or big)")
      ->type_name("W,H,TYPE[,ENDIAN]");
  app.add_option("--report,--stats", o.paths.report,
                 "Write the sizes, voids, height range, largest HAM, band rows and timings as "
                 "JSON");
  tool.add_threads_option();
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_build_ham(o, progress);
  });
}
