#include "spt/merge_spt.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "formats/rgb565.h"
#include "splatkit/common_origin.h"
#include "splatkit/crc32c.h"
#include "splatkit/error.h"
#include "spt/build_spt_tree.h"
#include "spt/spt_disc.h"

namespace splatkit::spt {

namespace {

// An entry of the merged list before quantisation: decoded values, in the common local frame.
struct Entry {
  Vec3f position, normal;
  float diameter, r_min, r_max;
  std::array<uint8_t, 3> color;
};

std::string number(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%g", v);
  return s;
}

// Refuses tile `t` unless it can join tile 0 in one list.
void check_tile(const SptModel& m, const std::string& name, const SptModel& first,
                const std::string& first_name) {
  const SptHeader& h = m.header;
  const SptHeader& f = first.header;
  auto differs = [&](const std::string& what, const std::string& mine, const std::string& theirs,
                     const std::string& hint) {
    throw_bad_input(name, what + " " + mine + " differs from " + first_name + "'s " + theirs +
                              " (" + hint + ")");
  };
  if (h.full() != f.full())
    differs("precision", h.full() ? "full" : "compact", f.full() ? "full" : "compact",
            "build the tiles with the same --precision");
  if (h.has_color() != f.has_color())
    differs("colour", h.has_color() ? "present" : "absent", f.has_color() ? "present" : "absent",
            "the tiles must all have colours or none");
  if (h.epsilon != f.epsilon)
    differs("epsilon", number(h.epsilon), number(f.epsilon),
            "build the tiles with the same --epsilon");
  if (h.color_weight != f.color_weight)
    differs("colour weight", number(h.color_weight), number(f.color_weight),
            "build the tiles with the same --color-weight");
}

// The index of the tile's root (its one entry with r_max = infinity: the first, the list being
// sorted by r_max descending).
std::size_t tile_root(const SptModel& m, const std::string& name) {
  if (m.size() == 0) throw_bad_input(name, "the list has no entries");
  if (!std::isinf(m.r_max[0])) throw_bad_input(name, "the list has no root (no r_max = infinity)");
  if (m.size() > 1 && std::isinf(m.r_max[1]))
    throw_bad_input(name,
                    "the list holds more than one tree (several entries with r_max = "
                    "infinity)");
  return 0;
}

// The upper tree over the tiles' roots, as build_spt_tree cuts its splats: a range of roots (in
// Morton order) splits at the highest level where neighbouring codes part.
struct Upper {
  const std::vector<uint8_t>& levels;
  const std::vector<SptDisc>& roots;  // in Morton order
  float color_weight;
  bool has_color;
  float epsilon;
  std::vector<Entry>& out;         // new nodes appended, post-order
  std::vector<float>& root_r_max;  // per root (Morton order): its parent's r_min
  std::vector<uint32_t>& root_depth;
  uint32_t depth = 0;

  // Returns the disc of range [b, e) and sets the r_max of its children.
  SptDisc build(std::size_t b, std::size_t e, uint32_t level_depth) {
    if (e - b == 1) {
      root_depth[b] = level_depth;
      return roots[b];
    }
    uint8_t top = 0;
    for (std::size_t i = b; i + 1 < e; ++i) top = std::max(top, levels[i]);
    std::vector<std::pair<std::size_t, std::size_t>> runs;
    std::size_t at = b;
    for (std::size_t i = b; i + 1 < e; ++i)
      if (levels[i] == top) {
        runs.emplace_back(at, i + 1);
        at = i + 1;
      }
    runs.emplace_back(at, e);
    std::vector<SptDisc> kids;
    std::vector<std::size_t> first_entry;  // each child's entry in `out` (new nodes), or none
    constexpr std::size_t kRoot = std::numeric_limits<std::size_t>::max();
    for (const auto& [rb, re] : runs) {
      kids.push_back(build(rb, re, level_depth + 1));
      first_entry.push_back(re - rb == 1 ? kRoot : out.size() - 1);
    }
    const SptDisc d = fit_spt_disc(kids, color_weight, has_color);
    const float r_min = std::min(d.error / epsilon, std::numeric_limits<float>::max());
    for (std::size_t k = 0; k < runs.size(); ++k) {
      if (first_entry[k] == kRoot)
        root_r_max[runs[k].first] = r_min;
      else
        out[first_entry[k]].r_max = r_min;
    }
    Entry n;
    n.position = d.centre;
    n.normal = d.normal;
    n.diameter = 2 * d.radius;
    n.r_min = r_min;
    n.r_max = INFINITY;  // set by the parent
    for (int j = 0; j < 3; ++j)
      n.color[j] =
          has_color ? static_cast<uint8_t>(std::clamp(std::lround(d.color[j]), 0L, 255L)) : 0;
    out.push_back(n);
    return d;
  }
};

}  // namespace

MergedSpt merge_spt(std::span<const SptModel> tiles, std::span<const std::string> names) {
  const std::size_t t_count = tiles.size();
  const SptHeader& h0 = tiles[0].header;
  for (std::size_t t = 0; t < t_count; ++t) {
    check_tile(tiles[t], names[t], tiles[0], names[0]);
    tile_root(tiles[t], names[t]);
  }
  const bool full = h0.full(), has_color = h0.has_color();
  // The tiles' positions in one frame: splat-tile gives most tiles the survey's origin, a tile
  // far from it its own (formats/tiles.md).
  std::vector<std::array<double, 3>> origins;
  for (const SptModel& m : tiles) origins.push_back(m.header.origin);
  const std::array<double, 3> origin = common_origin(origins);
  auto shifted = [&](const SptModel& m, const Vec3f& p) {
    if (m.header.origin == origin) return p;
    Vec3f q;
    for (int a = 0; a < 3; ++a)
      q[a] = static_cast<float>(m.header.origin[a] - origin[a] + double(p[a]));
    return q;
  };
  const float epsilon = h0.epsilon;

  // The box of every entry: the merged list's frame, and the cube the roots are coded over.
  constexpr float kInf = std::numeric_limits<float>::infinity();
  Bounds box{{kInf, kInf, kInf}, {-kInf, -kInf, -kInf}};
  for (const SptModel& m : tiles)
    for (std::size_t k = 0; k < m.size(); ++k) {
      const Vec3f p = shifted(m, m.positions[k]);
      for (int j = 0; j < 3; ++j) {
        box.min[j] = std::min(box.min[j], p[j]);
        box.max[j] = std::max(box.max[j], p[j]);
      }
    }

  // The tiles' roots as discs (error from r_min; the colour deviation is not stored: 0), put in
  // the Morton order of their centres over the cube of all entries: for tiles built in the
  // survey's cube (splat-tile's survey box), the cube of the whole build, so that the roots are
  // grouped as that build groups their cells.
  SptSplats roots;
  std::vector<SptDisc> root_discs(t_count);
  for (std::size_t t = 0; t < t_count; ++t) {
    const SptModel& m = tiles[t];
    SptDisc& d = root_discs[t];
    d.centre = shifted(m, m.positions[0]);
    d.normal = m.normals[0];
    d.radius = m.diameters[0] / 2;
    if (has_color) d.color = {float(m.colors[0][0]), float(m.colors[0][1]), float(m.colors[0][2])};
    d.error = m.r_min[0] * epsilon;
    roots.positions.push_back(d.centre);
    roots.normals.push_back(d.normal);
    roots.radii.push_back(d.radius);
  }
  std::vector<uint32_t> tile_of;  // Morton rank -> tile
  const SptOrder order = sort_spt_splats(roots, &tile_of, &box);
  std::vector<SptDisc> sorted(t_count);
  for (std::size_t i = 0; i < t_count; ++i) sorted[i] = root_discs[tile_of[i]];

  std::vector<Entry> upper;
  std::vector<float> root_r_max(t_count, INFINITY);
  std::vector<uint32_t> root_depth(t_count, 0);
  Upper u{order.levels, sorted, h0.color_weight, has_color, epsilon, upper, root_r_max, root_depth};
  u.build(0, t_count, 0);

  // Every entry: the tiles' in Morton order of their roots, each in its file's order, then the
  // new nodes bottom-up.
  std::vector<Entry> all;
  std::size_t total = upper.size();
  for (const SptModel& m : tiles) total += m.size();
  all.reserve(total);
  MergedSpt out;
  uint64_t input_points = 0;
  for (std::size_t i = 0; i < t_count; ++i) {
    const SptModel& m = tiles[tile_of[i]];
    for (std::size_t k = 0; k < m.size(); ++k) {
      Entry e{shifted(m, m.positions[k]),
              m.normals[k],
              m.diameters[k],
              m.r_min[k],
              k == 0 ? root_r_max[i] : m.r_max[k],
              has_color ? m.colors[k] : std::array<uint8_t, 3>{0, 0, 0}};
      all.push_back(e);
    }
    input_points += m.header.input_points;
    out.depth = std::max(out.depth, m.header.depth + root_depth[i]);
  }
  all.insert(all.end(), upper.begin(), upper.end());
  out.new_nodes = upper.size();

  // The merged frame and scales, as encode_spt states them: the box of the positions, the r
  // scale over the positive r values, the diameter scale over the positive diameters grown by
  // the new position error.
  SptHeader h;
  h.flags = (full ? kSptFlagFull : 0u) | (has_color ? kSptFlagColor : 0u);
  h.entry_bytes = full ? kSptFullEntryBytes : kSptCompactEntryBytes;
  h.depth = out.depth;
  h.input_points = input_points;
  h.origin = origin;
  h.epsilon = epsilon;
  h.color_weight = h0.color_weight;
  float r_lo = kInf, r_hi = 0, d_lo = kInf, d_hi = 0;
  for (const Entry& e : all) {
    if (e.r_min > 0) {
      r_lo = std::min(r_lo, e.r_min);
      r_hi = std::max(r_hi, e.r_min);
    }
    if (e.diameter > 0) {
      d_lo = std::min(d_lo, e.diameter);
      d_hi = std::max(d_hi, e.diameter);
    }
  }
  // (the new nodes lie in the hull of their children: the tiles' box holds them)
  h.box_min = box.min;
  h.step = {(box.max.x - box.min.x) / 65535.0f, (box.max.y - box.min.y) / 65535.0f,
            (box.max.z - box.min.z) / 65535.0f};
  // Tiles quantised in one frame (built over splat-tile's survey box, so the merged one):
  // their positions keep their codes, and the discs need not grow again.
  bool one_frame = !full;
  for (const SptModel& m : tiles)
    one_frame = one_frame && m.header.origin == origin && m.header.box_min == h0.box_min &&
                m.header.step == h0.step;
  if (one_frame) {
    h.box_min = h0.box_min;
    h.step = h0.step;
  }
  if (r_lo <= r_hi) {
    h.r_lo = r_lo;
    h.r_hi = r_hi;
  }
  const float slack =
      full || one_frame
          ? 0.0f
          : static_cast<float>(
                0.5 * std::hypot(double(h.step.x), double(h.step.y), double(h.step.z)) * 1.0001);
  constexpr float kMax = std::numeric_limits<float>::max();
  if (d_lo <= d_hi) {
    h.d_lo = std::min(d_lo + 2 * slack, kMax);
    h.d_hi = std::min((d_hi + 2 * slack) * 1.000001f, kMax);
  } else {
    h.d_lo = 1;
    h.d_hi = 1.000001f;
  }
  const LogScale rs = r_scale(h.r_lo, h.r_hi);
  const DiameterCoder diameter_code(d_scale(h.d_lo, h.d_hi));

  // Keys: the r_max (its code in compact lists); entries with an empty interval are left out.
  std::vector<uint32_t> kept;
  std::vector<uint16_t> min_code(full ? 0 : all.size()), max_code(full ? 0 : all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Entry& e = all[i];
    if (full) {
      if (e.r_max > e.r_min) kept.push_back(static_cast<uint32_t>(i));
      continue;
    }
    min_code[i] = encode_r(e.r_min, rs);
    max_code[i] = encode_r(e.r_max, rs);
    if (max_code[i] > min_code[i]) kept.push_back(static_cast<uint32_t>(i));
  }
  out.dropped_empty = all.size() - kept.size();
  if (full)
    std::stable_sort(kept.begin(), kept.end(),
                     [&](uint32_t a, uint32_t b) { return all[a].r_max > all[b].r_max; });
  else
    std::stable_sort(kept.begin(), kept.end(),
                     [&](uint32_t a, uint32_t b) { return max_code[a] > max_code[b]; });
  out.entries = kept.size();
  h.entries = kept.size();

  out.bytes.assign(kSptHeaderBytes + kept.size() * h.entry_bytes, 0);
  unsigned char* p = out.bytes.data() + kSptHeaderBytes;
  for (const uint32_t i : kept) {
    const Entry& e = all[i];
    if (full) {
      const float f[9] = {e.position.x, e.position.y, e.position.z, e.normal.x, e.normal.y,
                          e.normal.z,   e.diameter,   e.r_min,      e.r_max};
      for (int j = 0; j < 9; ++j) put_f32(p + 4 * j, f[j]);
      p[36] = e.color[0];
      p[37] = e.color[1];
      p[38] = e.color[2];
      p[39] = 0;
    } else {
      put_u16(p, encode_position(e.position.x, h.box_min.x, h.step.x));
      put_u16(p + 2, encode_position(e.position.y, h.box_min.y, h.step.y));
      put_u16(p + 4, encode_position(e.position.z, h.box_min.z, h.step.z));
      put_u16(p + 6, encode_normal(e.normal));
      put_u16(p + 8, diameter_code.encode(e.diameter > 0 ? e.diameter + 2 * slack : 0.0f));
      put_u16(p + 10, min_code[i]);
      put_u16(p + 12, max_code[i]);
      put_u16(p + 14, has_color ? encode_rgb565(e.color) : 0);
    }
    p += h.entry_bytes;
  }
  write_spt_header(h, out.bytes.data());
  uint32_t crc = crc32c(0, out.bytes.data(), 124);
  crc = crc32c(crc, out.bytes.data() + kSptHeaderBytes, out.bytes.size() - kSptHeaderBytes);
  h.checksum = crc;
  write_spt_header(h, out.bytes.data());
  return out;
}

}  // namespace splatkit::spt
