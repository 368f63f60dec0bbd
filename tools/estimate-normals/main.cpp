// estimate-normals: declares the options of apps::run_estimate_normals (lib/apps) and calls it.
#include "apps/run_estimate_normals.h"
#include "splatkit/tool.h"

int main(int argc, char** argv) {
  splatkit::Tool tool(
      "estimate-normals",
      "Estimate a unit normal and a splat radius for every point of a cloud (any input format): "
      "PCA over the k nearest neighbours (or a crease-preserving robust method); splats that cover "
      "the surface: each reaches the farthest corner of its point's Voronoi cell among its "
      "neighbours in its tangent plane (--radius cover), as circles or as ellipses fitted to the "
      "cells (--splat ellipse: far less overdraw on scan lines); orientation by visibility and "
      "smooth regions, over the kNN graph, up, or towards a viewpoint or sensor positions. Exact "
      "duplicate points are merged (the first one's "
      "colour and "
      "attributes are kept). OUT is .ply (binary) or .splk; '-' writes .splk to stdout.",
      "  $ estimate-normals scan.ply scan.splk\n"
      "  $ estimate-normals points.xyz points.ply --normals keep\n"
      "  $ estimate-normals survey.laz survey.splk --orient up\n"
      "  $ estimate-normals scan.las out.ply --orient viewpoint --viewpoint 0,0,1.8\n"
      "  $ estimate-normals part.xyz part.splk --method robust -k 24 --report part.json\n"
      "  $ estimate-normals scan.las scan.splk --splat ellipse\n"
      "  $ estimate-normals scan.laz scan.splk --outliers sor --outliers-out stray.ply\n"
      "  $ estimate-normals big.ply - --orient none --threads 2 | splat-info -\n");
  splatkit::apps::EstimateNormalsOptions o;
  auto& app = tool.app();
  tool.add_in_out(o.paths, "Input point cloud, any format ('-' = stdin)",
                  "Output .ply or .splk ('-' = .splk on stdout)");
  app.add_option("-k", o.normals.k,
                 "Points per PCA neighbourhood, the point included; with --method pca a point "
                 "whose k nearest show no plane (lambda0/lambda1 > 0.3: both faces of a thin "
                 "wall or slab) takes the normal of its 2k nearest (report: widened_points)")
      ->default_val(16)
      ->check(CLI::Range(std::size_t{3}, std::size_t{1024}));
  app.add_option("--radius", o.radius,
                 "cover: the splat covers its point's tangent-plane Voronoi cell among the row of "
                 "max(k, radius-k + 1) nearest points (no holes on irregular sampling); a cell "
                 "left open (a border) is cut at 2x the mean-knn radius, and half of it past a "
                 "border; mean-knn: the mean distance to the radius-k nearest "
                 "neighbours (leaves ~2.5 % of a random sample's surface uncovered)")
      ->check(CLI::IsMember({"cover", "mean-knn"}))
      ->default_str("cover");
  app.add_option("--splat", o.splat,
                 "circle, or ellipse: two tangent semi-axes fitted to the cover cell (elongated "
                 "where sampling is anisotropic, e.g. scan lines; written as axis_x/y/z and "
                 "minor_radius in PLY, an ELPS chunk in .splk); needs --radius cover")
      ->check(CLI::IsMember({"circle", "ellipse"}))
      ->default_str("circle");
  app.add_flag("--fit-centres", o.normals.fit_centres,
               "Move each splat centre along its normal onto the plane fitted to its point and "
               "its neighbours on the same sheet (needs --radius cover): on noisy scans the "
               "splats then lie on the surface and cover it; positions change by about the noise");
  app.add_option("--radius-k", o.normals.radius_k,
                 "Neighbours whose mean distance is the mean-knn radius (and, doubled, the cap of "
                 "the cover radius)")
      ->default_val(5)
      ->check(CLI::Range(std::size_t{1}, std::size_t{1024}));
  app.add_option("--radius-scale", o.normals.radius_scale, "Multiply every radius by S")
      ->default_val(1.0f)
      ->check(splatkit::positive_finite());
  app.add_option("--method", o.method, "pca, or robust (keeps creases sharp)")
      ->check(CLI::IsMember({"pca", "robust"}))
      ->default_val("pca");
  app.add_option("--orient", o.orient,
                 "auto (default): sensor when the input has per-point sensor positions, else "
                 "viewpoint when it records a scanner position, else visibility. visibility: "
                 "smooth regions (never across a crease or between the two sides of a thin "
                 "wall or slab), each region's sign from the sides of its splats seen from "
                 "directions above and around the scene (+z up), joined with the parity its "
                 "creases imply (on a tile of splat-tile, not through the borders where the "
                 "survey goes on); mst: consistent over the kNN graph alone (sheets joined across "
                 "creases by the majority of the edges between them), each set's top-most point "
                 "facing +z; up: towards +z (aerial scans); viewpoint: towards --viewpoint or "
                 "the input's scanner position; sensor: towards each point's sensor_x/y/z (or "
                 "scanner_*, vp_*) attributes; none: PCA's sign, made canonical (largest "
                 "component positive). The report says which ran and why")
      ->check(CLI::IsMember({"auto", "mst", "up", "viewpoint", "sensor", "visibility", "none"}))
      ->default_str("auto");
  app.add_option("--normals", o.normals_from,
                 "auto: a mesh's normals from its faces (area-weighted, oriented as they wind), "
                 "a point cloud's estimated (its own normals replaced, which the summary says); "
                 "keep: the input's valid normals kept as they are and used as evidence for "
                 "orienting the rest, estimated only where missing, zero or not unit length; "
                 "estimate: always estimated")
      ->check(CLI::IsMember({"auto", "estimate", "keep"}))
      ->default_str("auto");
  app.add_option("--viewpoint", o.viewpoint,
                 "Scanner position x,y,z in file coordinates (implies --orient viewpoint; "
                 "default: the input's own scanner position)");
  app.add_option("--max-radius-ratio", o.normals.max_radius_ratio,
                 "No splat radius above this many times the median radius of its 8 nearest "
                 "neighbours (no blobs at density jumps or stray points); 0 = no bound")
      ->default_val(splatkit::kDefaultMaxRadiusRatio);
  app.add_flag("--keep-duplicates", o.normals.keep_duplicates, "Do not merge exact duplicates");
  app.add_flag("--keep-order", o.keep_order,
               "Write the points in the input's order. By default they are written in a spatial "
               "order (Morton order, the same for any thread count), which makes the splat "
               "graph's file about a quarter smaller and the later stages up to 2x faster on "
               "shuffled input");
  app.add_option("--outliers", o.outliers,
                 "Remove outliers first, as PCL's filters do: sor:K,SIGMA drops points whose "
                 "mean distance to their K nearest neighbours is more than SIGMA standard "
                 "deviations above the cloud's mean; radius[:R,N] drops points with fewer than N "
                 "neighbours within R (default: R = 2x the median mean distance to the 8 "
                 "nearest, N = 6); plane:K,T drops points farther from the plane of their K "
                 "nearest neighbours than T times its RMS residual and 0.3x their mean distance; "
                 "passes joined by + run in turn, each on what the previous kept. sor alone is "
                 "sor:12,3+sor:6,3.5+plane:16,6, chosen by measurement (docs/design/normals.md): "
                 "the loose first pass removes the far outliers that inflate the deviation, the "
                 "second reaches "
                 "nearer ones, the plane pass those a spacing or two off the surface; with 1 % "
                 "outliers in the box it removed 86-97 % of them (97 % on an i.i.d. torus) and "
                 "at most 0.21 % of the scan on every scan measured, and 0.04-0.7 % of clean "
                 "scans, 3.9 % of a steep terrain (a single sor:12,1 removes 9-17 % of most "
                 "clean scans). The sor thresholds are global: where density falls off with "
                 "distance (a terrestrial scanner's far field) or jumps across the scan, the "
                 "sparse part is removed as outliers (a ground scan out to 30 m lost 91-99 % "
                 "of its points beyond 20 m): check --outliers-out, or crop such scans first; "
                 "none (default)")
      ->default_str("none");
  app.add_option("--outliers-out", o.outliers_out,
                 "Write the removed outliers here (any writable format, by extension)");
  app.add_option("--format", o.format, "Output format, overriding OUT's extension")
      ->check(CLI::IsMember({"ply", "splk"}));
  tool.add_columns_option(o.read.columns);
  app.add_option("--report,--stats", o.paths.report,
                 "Write counts, timings and peak RSS as JSON here");
  tool.add_threads_option();
  tool.add_memory_options(o.memory,
                          "The cloud is then processed piece by piece (pieces of about "
                          "SIZE/800 points, each with a halo of its neighbours), with the same "
                          "output as without a limit");
  return tool.run_stage(argc, argv, o.paths.output, [&](const splatkit::ProgressFn& progress) {
    return splatkit::apps::run_estimate_normals(o, progress);
  });
}
