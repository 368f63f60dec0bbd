#include "terrain/tessellate_tile.h"

#include <algorithm>

namespace splatkit::terrain {

namespace {

// Point k of n on the segment from a to b (a and b given in a fixed order for each edge).
double lerp(int64_t a, int64_t b, int k, int n) {
  return double(a) + double(b - a) * double(k) / double(n);
}

// Stitches polyline `outer` (o.size() ≥ 2) to polyline `inner` (≥ 1 points), both running the
// same way along one side, by always advancing on the one whose next point comes first.
void stitch(const std::vector<uint32_t>& o, const std::vector<double>& op,
            const std::vector<uint32_t>& in, const std::vector<double>& ip, TileMesh& m) {
  std::size_t i = 0, j = 0;
  while (i + 1 < o.size() || j + 1 < in.size()) {
    const bool advance_outer =
        j + 1 >= in.size() || (i + 1 < o.size() && op[i + 1] <= ip[j + 1]);
    if (advance_outer) {
      m.triangles.push_back({o[i], o[i + 1], in[j]});
      ++i;
    } else {
      m.triangles.push_back({o[i], in[j + 1], in[j]});
      ++j;
    }
  }
}

}  // namespace

uint64_t tile_triangle_count(const TileFactors& f) {
  const int n = std::max(1, f.inner);
  uint64_t count = 0;
  const uint64_t inner_side = n > 2 ? uint64_t(n - 2) : 0;  // segments of the inner ring's side
  for (int e = 0; e < 4; ++e) count += uint64_t(f.edge[std::size_t(e)]) + inner_side;
  if (n > 2) count += 2 * inner_side * inner_side;
  return count;
}

void tessellate_tile(const TileExtent& ex, const TileFactors& f, TileMesh& m) {
  const int n = std::max(1, f.inner);
  auto add = [&](double x, double y) {
    m.vertices.push_back({x, y});
    return uint32_t(m.vertices.size() - 1);
  };
  // Inner grid: points (i, j), 1 ≤ i, j ≤ n-1, at i/n of the tile; for n ≤ 2 the centre alone.
  const int g = n > 2 ? n - 1 : 1;  // inner points per side
  std::vector<uint32_t> grid(std::size_t(g * g));
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i)
      grid[std::size_t(j * g + i)] =
          n > 2 ? add(lerp(ex.x0, ex.x1, i + 1, n), lerp(ex.y0, ex.y1, j + 1, n))
                : add(0.5 * double(ex.x0 + ex.x1), 0.5 * double(ex.y0 + ex.y1));
  for (int j = 0; j + 1 < g; ++j)
    for (int i = 0; i + 1 < g; ++i) {
      const uint32_t a = grid[std::size_t(j * g + i)], b = grid[std::size_t(j * g + i + 1)];
      const uint32_t c = grid[std::size_t((j + 1) * g + i)], d = grid[std::size_t((j + 1) * g + i + 1)];
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  // The four sides, each from its lower-coordinate end: north (y0) and south (y1) run in x,
  // west (x0) and east (x1) run in y. Edge vertices from the edge's endpoints alone.
  struct Side {
    int edge;
    bool along_x;
    int64_t fixed;  // y for north/south, x for west/east
    int inner_fixed;  // the inner ring's row/column index
  };
  const Side sides[4] = {{0, true, ex.y0, 0}, {2, true, ex.y1, g - 1},
                         {3, false, ex.x0, 0}, {1, false, ex.x1, g - 1}};
  for (const Side& s : sides) {
    const int fe = std::max(1, f.edge[std::size_t(s.edge)]);
    std::vector<uint32_t> o, in;
    std::vector<double> op, ip;
    for (int k = 0; k <= fe; ++k) {
      const double t = lerp(s.along_x ? ex.x0 : ex.y0, s.along_x ? ex.x1 : ex.y1, k, fe);
      o.push_back(s.along_x ? add(t, double(s.fixed)) : add(double(s.fixed), t));
      op.push_back(double(k) / double(fe));
    }
    for (int k = 0; k < g; ++k) {
      in.push_back(s.along_x ? grid[std::size_t(s.inner_fixed * g + k)]
                             : grid[std::size_t(k * g + s.inner_fixed)]);
      ip.push_back(g > 1 ? double(k) / double(g - 1) : 0.0);
    }
    // Inner points sit at (k+1)/n of the side: compare positions, not indices.
    for (int k = 0; k < g && n > 2; ++k) ip[std::size_t(k)] = double(k + 1) / double(n);
    if (n <= 2) ip[0] = 0.5;
    stitch(o, op, in, ip, m);
  }
}

}  // namespace splatkit::terrain
