// splat-view: declares the options of apps::run_splat_view (lib/apps) and calls it; --serve
// calls serve::serve_files (lib/serve) instead.
#include <cstdio>

#include "apps/run_splat_view.h"
#include "apps/run_terrain_view.h"
#include "render/reconstruct_pixel.h"
#include "render/setup_splats.h"
#include "serve/serve_files.h"
#include "splatkit/error.h"
#include "splatkit/progress.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "splat-view",
      "Render a splat file (positions, normals, radii, optional colours) to an image; QSplat .qs "
      "and Sequential Point Tree .spt files are drawn by level of detail. With --serve, show "
      "files in a web browser instead (WebGL2 viewer on http://127.0.0.1 only)",
      "$ splat-view bunny.splk bunny.png                    # default three-quarter view\n"
      "$ splat-view scan.splk top.png --view 0,90 --width 1920 --height 1080  # a map, +y up\n"
      "$ splat-view part.splk part.exr --eye 3,2,1 --target 0,0,0  # float colour + Z, N AOVs\n"
      "$ splat-view part.splk 'turn_%04d.png' --turntable 36 --report stats.json\n"
      "$ splat-view part-surf.splk surf.png --shade surface   # after segment-surfaces\n"
      "$ splat-view bunny.qs far.png --qsplat-threshold 4      # QSplat traversal, 4 px\n"
      "$ splat-view scan.spt far.png --spt-error 2 --stats s.json  # Sequential Point Tree\n"
      "$ splat-view part-graph.splk soft.png --no-clip        # compare with clipping off\n"
      "$ splat-view city.splk 'walk_%04d.png' --path city.path.json --occlusion chc++\n"
      "$ splat-view --terrain dem.tif --ham tiles.exr dem.png --wireframe  # after build-ham\n"
      "The browser viewer runs until Ctrl-C:\n"
      "  splat-view --serve scan.spt bunny.qs part.splk --port 8080\n"
      "  then open http://127.0.0.1:8080/#file=scan.spt&view=35,25 (the camera of --view 35,25)\n");
  tool.add_threads_option();
  CLI::App& app = tool.app();
  splatkit::apps::SplatViewOptions o;
  namespace render = splatkit::render;
  std::string positional_out;
  app.add_option("IN", o.input,
                 "Splat file (any format estimate-normals writes, .splk, .qs, .spt); with "
                 "--terrain the only argument is OUT");
  app.add_option("OUT", positional_out, "The image (as -o)");
  std::string output_option;
  std::vector<std::string> serve;
  int port = 0;
  app.add_option("--serve", serve,
                 "Serve these files to the browser viewer (WebGL2: .spt drawn on the GPU by "
                 "its distance intervals, .qs by the QSplat traversal per frame, other splat files "
                 "as blended splats) on 127.0.0.1 only, print its URL, and run until Ctrl-C. "
                 "http://127.0.0.1:PORT/#file=NAME&view=AZ,EL[,DIST] shows NAME as --view does "
                 "at the window's size. Only the named files are served, under their base names")
      ->expected(1, -1)
      ->type_name("FILE...");
  app.add_option("--port", port, "With --serve: the port (0: any free port)")
      ->default_val(0)
      ->check(CLI::Range(0, 65535));
  app.add_option("-o,--output", output_option,
                 "Image: .png (8-bit sRGB) or .exr (float RGBA + Z, N.X N.Y N.Z, and a uint "
                 "surface_id channel when the file has surface ids and --no-surface-ids is not "
                 "given); no other format. '-' = PNG to stdout. A frame number field such as "
                 "%04d only with --turntable or --path. The same as OUT (give one of them)");
  app.add_option("--eye", o.eye,
                 "Camera position x,y,z, in the file's coordinates (georeferenced ones too; "
                 "with --terrain the map's: longitude, latitude and height for a lon/lat DEM, "
                 "projected x, y for a projected one, column, -row without georeferencing)")
      ->type_name("X,Y,Z");
  app.add_option("--target", o.target,
                 "Point looked at x,y,z, in the file's coordinates (default: model centre)")
      ->type_name("X,Y,Z");
  app.add_option("--up", o.up,
                 "Up direction x,y,z (default 0,0,1); turntables turn about it. A top or bottom "
                 "view (within 0.81 degrees of it: --view AZ,90, or --eye straight above the "
                 "target) takes the axis at azimuth 90 as the image's up: +y for the default, so "
                 "a top view is a map with +x right and +y up. With --eye, an --up given and "
                 "parallel to the view is an error")
      ->type_name("X,Y,Z");
  app.add_option("--fov", o.fov_y_deg, "Vertical field of view, degrees, in (0, 180)")
      ->default_val(40);
  app.add_option("--view", o.view,
                 "Orbit view AZ,EL[,DIST]: degrees around --up and above the horizon, distance "
                 "from the model centre (scene units; default frames the model)")
      ->type_name("AZ,EL[,DIST]");
  app.add_option("--width", o.width, "Image width, pixels")
      ->default_val(1280)
      ->check(CLI::Range(1, render::kMaxImageSide));
  app.add_option("--height", o.height, "Image height, pixels")
      ->default_val(720)
      ->check(CLI::Range(1, render::kMaxImageSide));
  app.add_option("--turntable", o.turntable,
                 "Render N frames in one turn around the model; OUT needs a %04d field")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--blend", o.blend,
                 "Surface reconstruction: zthreshold[=EPS] (EPS in scene units, default twice "
                 "the mean splat radius), zrange, or zbuffer: no blending, each pixel shows its "
                 "nearest splat drawn as its disc (the pixels whose rays hit it; the fast path "
                 "for splats of a few pixels, as QSplat draws; no clipping, aliased edges; .spt "
                 "entries of at most 1.5 px are one pixel each)")
      ->default_val("zthreshold");
  app.add_option("--shade", o.shade,
                 "phong, normals, depth, flat (unlit albedo), or false colours lit with phong: "
                 "surface (a colour per surface id; needs segment-surfaces output), sharp "
                 "(splats with a sharp edge red, the rest green; needs build-splat-graph "
                 "output), clipped (splats with clip partners orange; needs a .splk from "
                 "build-splat-graph)")
      ->default_val("phong")
      ->check(CLI::IsMember({"phong", "normals", "depth", "flat", "surface", "sharp", "clipped"}));
  app.add_option("--max-fragments", o.render.max_fragments,
                 "A-buffer slots per pixel; on overflow the farthest fragment is dropped")
      ->default_val(8)
      ->check(CLI::Range(1, render::kMaxFragmentsPerPixel));
  app.add_flag("--cull-backfaces", o.render.cull_backfaces,
               "Skip splats facing away, and QSplat nodes whose normal cone faces away "
               "(closed, consistently oriented models only)");
  app.add_option("--qsplat-threshold", o.render.qsplat_threshold_px,
                 "QSplat .qs input: recurse until a node's projected size is at most PX pixels "
                 "(0.25 to 50); nodes are drawn as discs of their sphere's size")
      ->default_val(1.0f)
      ->type_name("PX")
      ->check(splatkit::finite_range(0.25, 50.0));
  app.add_option("--spt-error", o.render.spt_error_px,
                 "Sequential Point Tree .spt input (build-spt): the allowed screen error in "
                 "pixels; an entry is drawn where its error over its distance is within it, as "
                 "a disc of its diameter (0.1 to 50)")
      ->default_val(1.0f)
      ->type_name("PX")
      ->check(splatkit::finite_range(0.1, 50.0));
  app.add_flag("!--no-clip", o.render.clip,
               "Ignore the file's clip partners (CLIP chunk): edges as plain splats give them");
  app.add_flag("!--no-surface-ids", o.render.surface_ids,
               "Ignore the file's surface ids (SURF chunk, else a surface_id attribute) in "
               "reconstruction: fragments of different surfaces blend");
  app.add_option("--background", o.background, "Background colour R,G,B (sRGB, each in 0..1)")
      ->type_name("R,G,B");
  app.add_option("--path", o.path,
                 "Camera path: a JSON array of {\"eye\": [x,y,z], \"target\": [x,y,z]} with "
                 "optional \"up\" and \"fov\" (points in the file's coordinates); one frame per "
                 "camera, OUT needs a %04d field; '-' reads it from standard input")
      ->type_name("CAMERAS.json");
  app.add_option("--occlusion", o.occlusion,
                 "Occlusion culling over a hierarchy of splat chunks built at load: none, "
                 "frustum, hierarchical (a depth-pyramid query per node), chc or chc++ "
                 "(coherent hierarchical culling, Bittner et al. 2004; Mattausch et al. 2008). "
                 "Every mode gives the same image; plain splat files, A-buffer blends")
      ->default_val("none")
      ->check(CLI::IsMember({"none", "frustum", "hierarchical", "chc", "chc++"}));
  app.add_option("--bvh-split", o.bvh_split,
                 "Chunk hierarchy split: median (of the centres along the longest axis) or sah "
                 "(surface area heuristic)")
      ->default_val("median")
      ->check(CLI::IsMember({"median", "sah"}));
  app.add_option("--bvh-leaf", o.bvh_leaf, "Splats per chunk (hierarchy leaf), at most")
      ->default_val(2048)
      ->check(CLI::Range(1u, 1u << 24));
  app.add_flag("--count-visible", o.count_visible,
               "Diagnostic: count the splats each frame truly shows (nearest splat ids of a "
               "z-buffer pass) into the --stats report as occlusion.splats_visible, and the time "
               "to render those splats alone as occlusion.floor_ms (the least any culling could "
               "leave)");
  app.add_option("--report,--stats", o.stats_path,
                 "Write a JSON report (counts, time per stage). With several frames, \"frames\" "
                 "holds each frame's counts and times, \"mean_frame_ms\" and the occlusion "
                 "totals all of them, and the top-level counts are the last frame's");
  splatkit::apps::TerrainViewOptions terrain;
  CLI::Option* terrain_option =
      app.add_option(
             "--terrain", terrain.heightmap,
             "Render this heightmap (any build-ham input) instead of splats, tessellated per "
             "tile by --ham; every pixel is shaded from the map at the texel it shows (the "
             "triangles place silhouettes and depth)")
          ->type_name("HEIGHTMAP");
  app.add_option("--ham", terrain.ham, "With --terrain: build-ham's per-tile HAM EXR")
      ->type_name("TILES.exr")
      ->needs(terrain_option);
  app.add_option("--tess-error", terrain.tess_error_px,
                 "With --terrain: allowed screen-space error of the triangles' heights, pixels "
                 "(> 0): smaller draws more; small enough (0.01 to 0.001 for a whole-map view) "
                 "every tile with any curvature reaches the map's full resolution, one texel per "
                 "triangle edge (tiles of up to 64 texels), flat tiles stay coarse; the shading "
                 "is per pixel whatever the error")
      ->default_val(2.0f)
      ->check(splatkit::positive_finite())
      ->needs(terrain_option);
  app.add_option("--tess-distance", terrain.tess_distance_tiles,
                 "With --terrain: full tessellation within this many tile diagonals of the eye")
      ->default_val(3.0f)
      ->check(splatkit::positive_finite())
      ->needs(terrain_option);
  app.add_option("--raw", terrain.raw, "With --terrain: the heightmap is headerless RAW")
      ->type_name("W,H,TYPE[,ENDIAN]")
      ->needs(terrain_option);
  app.add_flag("--wireframe", terrain.wireframe, "With --terrain: draw the triangles' edges")
      ->needs(terrain_option);
  tool.reuse_freed_blocks();  // every frame allocates its buffers again
  return tool.run(argc, argv, [&] {
    if (!serve.empty()) {
      if (!output_option.empty() || !terrain.heightmap.empty() || !o.input.empty())
        splatkit::throw_usage(
            "--serve shows files in the browser; it takes no IN, OUT, -o or --terrain");
      splatkit::serve::serve_files({serve, port}, [](const std::string& url) {
        std::printf("splat-view: serving on %s (Ctrl-C stops)\n", url.c_str());
        std::fflush(stdout);
      });
      return;
    }
    if (app.count("--port") > 0) splatkit::throw_usage("--port goes with --serve");
    std::vector<std::string> positional;
    for (const std::string* a : {&o.input, &positional_out})
      if (!a->empty()) positional.push_back(*a);
    o.input.clear();
    const std::size_t inputs = terrain.heightmap.empty() ? 1 : 0;
    if (positional.size() > inputs + 1)
      splatkit::throw_usage("with --terrain give only OUT (the heightmap is --terrain's)");
    if (inputs == 1 && positional.empty())
      splatkit::throw_usage("input is required (a splat file, or --terrain HEIGHTMAP)");
    if (inputs == 1) o.input = positional[0];
    if (positional.size() == inputs + 1) {
      if (!output_option.empty())
        splatkit::throw_usage("OUT given twice: as an argument and as -o; give one");
      o.output = positional[inputs];
    } else {
      o.output = output_option;
    }
    if (o.output.empty()) splatkit::throw_usage("OUT is required (IN OUT, or -o OUT)");
    splatkit::Progress progress("splat-view", tool.quiet() || o.output == "-");
    const splatkit::apps::StageSummary summary =
        terrain.heightmap.empty()
            ? splatkit::apps::run_splat_view(o, progress.callback()).line()
            : splatkit::apps::run_terrain_view(o, terrain, progress.callback());
    progress.finish(summary.count, summary.unit, summary.extra);
  });
}
