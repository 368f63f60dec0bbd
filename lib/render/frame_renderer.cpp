#include "render/frame_renderer.h"

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include "formats/qsplat_codes.h"
#include "render/rasterize_tile.h"
#include "render/select_qsplat.h"
#include "render/select_splats.h"
#include "render/select_spt.h"
#include "render/shade_row.h"
#include "render/zbuffer_splats.h"
#include "splatkit/error.h"

namespace splatkit::render {

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// sRGB encoding of linear [0, 1] to 8 bits through a table fine enough to be exact for every
// code value above the linear toe.
class SrgbEncoder {
 public:
  SrgbEncoder() {
    for (int i = 0; i < kSize; ++i) {
      float v = linear_to_srgb((i + 0.5f) / kSize);
      table_[i] = static_cast<uint8_t>(std::lround(v * 255.0f));
    }
  }
  uint8_t operator()(float linear) const {
    return table_[static_cast<int>(std::clamp(linear, 0.0f, 1.0f) * (kSize - 1))];
  }

 private:
  static constexpr int kSize = 1 << 16;
  std::array<uint8_t, kSize> table_;
};

const SrgbEncoder& srgb_encoder() {
  static const SrgbEncoder encoder;
  return encoder;
}

uint8_t to_byte(float v) {
  return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255));
}

struct TileCounters {
  uint64_t fragments = 0, covered = 0, overflowed = 0, skipped = 0, clipped = 0;
  double raster_s = 0, reconstruct_s = 0, shade_s = 0;
};

// One thread's tile A-buffer, tile G-buffer and counters, reused from tile to tile.
struct TileScratch {
  FragmentStore store;
  std::vector<PixelSurface> gbuffer;
  TileCounters counters;
};

}  // namespace

struct FrameRenderer::Scratch {
  tbb::enumerable_thread_specific<TileScratch> threads;
  DepthKeyBuffer zbuffer;
};

FrameRenderer::FrameRenderer() : scratch_(std::make_unique<Scratch>()) {}
FrameRenderer::~FrameRenderer() = default;

namespace {

struct FrameContext {
  const DrawList& draws;
  const FrameBins& bins;
  const Projection& projection;
  const RenderOptions& options;
  const BlendOptions& blend;
  const Shading& shading;
  const ClipContext* clip;  // null: no clipping this frame
  Framebuffer& out;
  uint8_t background_rgb8[3];
};

// The bytes of one pixel of the rgb8 plane.
inline void encode_rgb8(const FrameContext& f, const Vec3f& color, uint8_t* px) {
  if (f.shading.linear_output) {
    const SrgbEncoder& enc = srgb_encoder();
    px[0] = enc(color.x);
    px[1] = enc(color.y);
    px[2] = enc(color.z);
  } else {
    px[0] = to_byte(color.x);
    px[1] = to_byte(color.y);
    px[2] = to_byte(color.z);
  }
}

void write_background(const FrameContext& f, std::size_t p) {
  Framebuffer& out = f.out;
  if (out.planes.rgb8) std::memcpy(out.rgb8.data() + 3 * p, f.background_rgb8, 3);
  if (out.planes.float_color) std::fill_n(out.rgba.data() + 4 * p, 4, 0.0f);
  if (out.planes.aovs) {
    out.depth[p] = std::numeric_limits<float>::infinity();
    std::fill_n(out.normal.data() + 3 * p, 3, 0.0f);
    out.alpha[p] = 0;
  }
  if (out.planes.surface_ids) out.surface_id[p] = kNoSurfaceId;
}

void write_surface(const FrameContext& f, std::size_t p, const PixelSurface& s,
                   const Vec3f& color) {
  Framebuffer& out = f.out;
  if (out.planes.rgb8) encode_rgb8(f, color, out.rgb8.data() + 3 * p);
  if (out.planes.float_color) {
    float* px = out.rgba.data() + 4 * p;
    px[0] = color.x * s.alpha;
    px[1] = color.y * s.alpha;
    px[2] = color.z * s.alpha;
    px[3] = s.alpha;
  }
  if (out.planes.aovs) {
    out.depth[p] = s.depth;
    const Vec3f n = normalized(s.normal);
    out.normal[3 * p] = n.x;
    out.normal[3 * p + 1] = n.y;
    out.normal[3 * p + 2] = n.z;
    out.alpha[p] = s.alpha;
  }
  if (out.planes.surface_ids) out.surface_id[p] = s.surface_id;
}

// Only the 8-bit plane, sRGB-encoded (PNG output, the usual case): the row writers below then
// take loops without per-pixel plane tests.
bool rgb8_only(const FrameContext& f) {
  const FramebufferPlanes& p = f.out.planes;
  return p.rgb8 && !p.float_color && !p.aovs && !p.surface_ids && f.shading.linear_output;
}

// Pixels (x0 + i, y), i < count, as background.
void write_background_row(const FrameContext& f, int x0, int y, int count) {
  const std::size_t first = std::size_t(y) * f.out.width + x0;
  if (!rgb8_only(f)) {
    for (int i = 0; i < count; ++i) write_background(f, first + i);
    return;
  }
  uint8_t* px = f.out.rgb8.data() + 3 * first;
  for (int i = 0; i < count; ++i, px += 3) std::memcpy(px, f.background_rgb8, 3);
}

// Pixels (x0 + i, y), i < count, from their G-buffer entries and shaded colours.
void write_row(const FrameContext& f, int x0, int y, int count, const PixelSurface* g,
               const Vec3f* colors) {
  const std::size_t first = std::size_t(y) * f.out.width + x0;
  if (!rgb8_only(f)) {
    for (int i = 0; i < count; ++i) {
      if (g[i].alpha == 0)
        write_background(f, first + i);
      else
        write_surface(f, first + i, g[i], colors[i]);
    }
    return;
  }
  const SrgbEncoder& enc = srgb_encoder();
  uint8_t* px = f.out.rgb8.data() + 3 * first;
  for (int i = 0; i < count; ++i, px += 3) {
    if (g[i].alpha == 0) {
      std::memcpy(px, f.background_rgb8, 3);
    } else {
      px[0] = enc(colors[i].x);
      px[1] = enc(colors[i].y);
      px[2] = enc(colors[i].z);
    }
  }
}

void render_tile(const FrameContext& f, std::size_t t, TileScratch& local) {
  const int tx = static_cast<int>(t % f.bins.tiles_x), ty = static_cast<int>(t / f.bins.tiles_x);
  TileRect rect{tx * kTileSize, ty * kTileSize,
                std::min(f.projection.width, (tx + 1) * kTileSize) - 1,
                std::min(f.projection.height, (ty + 1) * kTileSize) - 1};
  const int pixels = rect.width() * rect.height();
  const Projection& pr = f.projection;
  const uint32_t begin = f.bins.offsets[t], end = f.bins.offsets[t + 1];
  if (begin == end) {
    auto t0 = Clock::now();
    for (int y = rect.y0; y <= rect.y1; ++y) write_background_row(f, rect.x0, y, rect.width());
    local.counters.shade_s += seconds(t0, Clock::now());
    return;
  }
  auto t0 = Clock::now();
  local.store.reset(pixels, f.options.max_fragments, f.blend.window);
  const RasterCounts raster = rasterize_tile(f.bins.rasters.get(), f.bins.indices.data() + begin,
                                             end - begin, rect, local.store, f.clip);
  local.counters.fragments += raster.fragments;
  local.counters.clipped += raster.clipped;
  local.counters.skipped += raster.skipped_splats;
  auto t1 = Clock::now();
  local.gbuffer.resize(pixels);
  local.counters.covered += reconstruct_pixels(
      local.store, pixels, f.draws, f.bins.rasters.get(), f.blend, f.options.default_albedo,
      {&pr, rect.x0, rect.y0, rect.width()}, local.gbuffer.data(), local.counters.overflowed);
  auto t2 = Clock::now();
  // Shaded a row at a time (shade_row.h): background pixels are shaded too, for nothing, but
  // that keeps the loops free of branches.
  static_assert(kTileSize <= kMaxShadeRun);
  Vec3f colors[kMaxShadeRun];
  for (int y = rect.y0, p = 0; y <= rect.y1; ++y, p += rect.width()) {
    shade_row(f.shading, pr, rect.x0, y, rect.width(), &local.gbuffer[p], colors);
    write_row(f, rect.x0, y, rect.width(), &local.gbuffer[p], colors);
  }
  auto t3 = Clock::now();
  local.counters.raster_s += seconds(t0, t1);
  local.counters.reconstruct_s += seconds(t1, t2);
  local.counters.shade_s += seconds(t2, t3);
}

// The framebuffer from a depth-key buffer: rows in parallel, each in runs of a tile's width, the
// pixel's splat made a G-buffer entry by surface(index, entry) (normal, albedo, surface id), then
// shaded and written as the tiles are.
template <class Surface>
void resolve_zbuffer(const FrameContext& f, const DepthKeyBuffer& b, Surface surface) {
  tbb::parallel_for(tbb::blocked_range<int>(0, b.height, 8), [&](const auto& rows) {
    PixelSurface g[kMaxShadeRun];
    Vec3f colors[kMaxShadeRun];
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x0 = 0; x0 < b.width; x0 += kMaxShadeRun) {
        const int count = std::min(kMaxShadeRun, b.width - x0);
        const uint64_t* keys = b.keys.data() + std::size_t(y) * b.width + x0;
        if (std::all_of(keys, keys + count, [](uint64_t k) { return k == kNoSplatKey; })) {
          write_background_row(f, x0, y, count);
          continue;
        }
        for (int i = 0; i < count; ++i) {
          g[i] = PixelSurface{};
          if (keys[i] == kNoSplatKey) continue;
          surface(DepthKeyBuffer::index_of(keys[i]), g[i]);
          g[i].depth = DepthKeyBuffer::depth_of(keys[i]);
          g[i].alpha = 1;
        }
        shade_row(f.shading, f.projection, x0, y, count, g, colors);
        write_row(f, x0, y, count, g, colors);
      }
  });
}

void check_options(const RenderOptions& o) {
  if (!(o.spt_error_px > 0) || !std::isfinite(o.spt_error_px))
    throw_usage("--spt-error must be a positive number of pixels");
  if (o.max_fragments < 1 || o.max_fragments > kMaxFragmentsPerPixel)
    throw_usage("--max-fragments must be in 1.." + std::to_string(kMaxFragmentsPerPixel));
  if (o.blend == BlendMode::kZThreshold && !(std::isfinite(o.epsilon)))
    throw_usage("the Z-threshold epsilon must be finite");
}

}  // namespace

FrameStats FrameRenderer::render(const RenderScene& scene, const Camera& camera,
                                 const RenderOptions& options, Framebuffer& out) {
  check_options(options);
  const auto start = Clock::now();
  const Projection projection = make_projection(camera);
  if (options.blend == BlendMode::kZBuffer) return render_zbuffer(scene, projection, options, out);
  FrameStats stats;
  DrawList draws = select_splats(scene, projection, options.qsplat_threshold_px, &stats.lod,
                                 options.spt_error_px, options.cull_backfaces);
  if (!options.surface_ids) draws.surface_ids = nullptr;
  if (!options.clip) {
    draws.clip = nullptr;
    draws.clip_planes = nullptr;
  }
  const auto selected = Clock::now();
  stats.select_s = seconds(start, selected);
  stats.splats_in = draws.count;

  bin_splats(draws, projection, SetupOptions{options.cull_backfaces}, bins_);
  stats.splats_drawn = bins_.drawn;
  stats.setup_s = bins_.setup_seconds;
  stats.binning_s = bins_.binning_seconds;

  out.allocate(camera.width, camera.height, options.planes);
  BlendOptions blend;
  blend.mode = options.blend;
  blend.epsilon = options.epsilon > 0 ? options.epsilon : 2.0f * scene.mean_radius;
  blend.window = depth_window(blend.mode, blend.epsilon, scene.max_radius, options.max_fragments);
  const Shading shading = make_shading(options.shade, projection, scene.bounds);
  ClipContext clip{draws.clip, draws.clip_planes, projection};
  FrameContext context{
      draws, bins_, projection, options, blend, shading, draws.clip ? &clip : nullptr, out, {}};
  const SrgbEncoder& enc = srgb_encoder();
  context.background_rgb8[0] = enc(options.background.x);
  context.background_rgb8[1] = enc(options.background.y);
  context.background_rgb8[2] = enc(options.background.z);
  for (auto& local : scratch_->threads) local.counters = {};
  const auto tiles_start = Clock::now();
  tbb::parallel_for(std::size_t{0}, bins_.tile_count(),
                    [&](std::size_t t) { render_tile(context, t, scratch_->threads.local()); });
  const auto tiles_end = Clock::now();

  TileCounters sum;
  for (const auto& local : scratch_->threads) {
    sum.fragments += local.counters.fragments;
    sum.covered += local.counters.covered;
    sum.overflowed += local.counters.overflowed;
    sum.skipped += local.counters.skipped;
    sum.clipped += local.counters.clipped;
    sum.raster_s += local.counters.raster_s;
    sum.reconstruct_s += local.counters.reconstruct_s;
    sum.shade_s += local.counters.shade_s;
  }
  stats.fragments = sum.fragments;
  stats.pixels_covered = sum.covered;
  stats.pixels_overflowed = sum.overflowed;
  stats.splats_hidden = sum.skipped;
  stats.fragments_clipped = sum.clipped;
  const double tiles_wall = seconds(tiles_start, tiles_end);
  const double cpu = sum.raster_s + sum.reconstruct_s + sum.shade_s;
  if (cpu > 0) {
    stats.raster_s = tiles_wall * sum.raster_s / cpu;
    stats.reconstruct_s = tiles_wall * sum.reconstruct_s / cpu;
    stats.shade_s = tiles_wall * sum.shade_s / cpu;
  }
  stats.total_s = seconds(start, tiles_end);
  return stats;
}

FrameStats FrameRenderer::render_zbuffer(const RenderScene& scene, const Projection& projection,
                                         const RenderOptions& options, Framebuffer& out) {
  const auto start = Clock::now();
  FrameStats stats;
  DepthKeyBuffer& zb = scratch_->zbuffer;
  zb.reset(projection.width, projection.height);
  const auto cleared = Clock::now();
  stats.setup_s = seconds(start, cleared);  // clearing the buffer
  DrawList draws;
  if (scene.qsplat) {
    const QSplatZBufferCounts c = draw_qsplat_zbuffer(
        *scene.qsplat, projection, options.qsplat_threshold_px, options.cull_backfaces, zb);
    stats.lod = c.lod;
    stats.splats_in = c.selected;
    stats.splats_drawn = c.drawn;
    stats.select_s = seconds(cleared, Clock::now());
  } else if (scene.spt) {
    const SptZBufferCounts c =
        draw_spt_zbuffer(*scene.spt, scene.bounds, projection, options.spt_error_px, zb);
    stats.lod.spt_prefix = c.prefix;
    stats.lod.spt_culled = c.prefix - c.selected;
    stats.lod.spt_points = c.points;
    stats.lod.spt_diameter_px_sum = c.diameter_px_sum;
    stats.lod.spt_cpu_s = c.cpu_s;
    stats.splats_in = c.selected;
    stats.splats_drawn = c.drawn;
    stats.select_s = seconds(cleared, Clock::now());
  } else {
    draws = select_splats(scene, projection, options.qsplat_threshold_px, &stats.lod,
                          options.spt_error_px, options.cull_backfaces);
    stats.splats_in = draws.count;
    const bool cull = options.cull_backfaces;
    stats.splats_drawn = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, draws.count, 1 << 14), uint64_t{0},
        [&](const auto& r, uint64_t n) {
          for (std::size_t i = r.begin(); i < r.end(); ++i) {
            if (cull && dot(draws.normals[i], draws.positions[i] - projection.eye) > 0) continue;
            n += zbuffer_disc(
                zb, projection, projection.to_camera(draws.positions[i]),
                [&] { return camera_direction(projection, draws.normals[i]); }, draws.radii[i],
                static_cast<uint32_t>(i));
          }
          return n;
        },
        std::plus<>());
    stats.raster_s = seconds(cleared, Clock::now());
  }
  const auto drawn = Clock::now();
  out.allocate(projection.width, projection.height, options.planes);
  const BlendOptions blend;
  const Shading shading = make_shading(options.shade, projection, scene.bounds);
  FrameContext context{draws, bins_, projection, options, blend, shading, nullptr, out, {}};
  const SrgbEncoder& enc = srgb_encoder();
  context.background_rgb8[0] = enc(options.background.x);
  context.background_rgb8[1] = enc(options.background.y);
  context.background_rgb8[2] = enc(options.background.z);
  const Vec3f albedo = options.default_albedo;
  if (scene.qsplat) {
    const QSplatModel& m = *scene.qsplat;
    const auto& palette = linear_palette_565();
    resolve_zbuffer(context, zb, [&](uint32_t i, PixelSurface& g) {
      g.normal = qsplat::decode_normal(m.normal_codes[i]);
      g.albedo = m.colors.empty() ? albedo : palette[m.colors[i]];
    });
  } else if (scene.spt) {
    const SptModel& m = *scene.spt;
    resolve_zbuffer(context, zb, [&](uint32_t i, PixelSurface& g) {
      g.normal = m.normals[i];
      g.albedo = m.colors.empty() ? albedo : spt_linear_color(m.colors[i]);
    });
  } else {
    const uint32_t* ids = options.surface_ids ? draws.surface_ids : nullptr;
    resolve_zbuffer(context, zb, [&](uint32_t i, PixelSurface& g) {
      g.normal = draws.normals[i];
      g.albedo = draws.colors ? draws.colors[i] : albedo;
      g.surface_id = ids ? ids[i] : 0;
    });
  }
  const auto end = Clock::now();
  stats.shade_s = seconds(drawn, end);
  stats.total_s = seconds(start, end);
  return stats;
}

}  // namespace splatkit::render
