#include "spt/encode_spt.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "formats/spt_codes.h"
#include "splatkit/crc32c.h"

namespace splatkit::spt {

namespace {

struct NodeView {
  const SptTree& tree;
  const SptInput& in;
  std::size_t n;
  Vec3f centre(std::size_t i) const {
    return i < n ? in.positions[i] : tree.interiors[i - n].centre;
  }
  Vec3f normal(std::size_t i) const { return i < n ? in.normals[i] : tree.interiors[i - n].normal; }
  float radius(std::size_t i) const { return i < n ? in.radii[i] : tree.interiors[i - n].radius; }
  std::array<uint8_t, 3> color(std::size_t i) const {
    const Vec3f c = i < n ? in.leaf(i).color : tree.interiors[i - n].color;
    auto q = [](float v) {
      return static_cast<uint8_t>(std::clamp(std::floor(v + 0.5f), 0.0f, 255.0f));
    };
    return {q(c.x), q(c.y), q(c.z)};
  }
};

}  // namespace

EncodedSpt encode_spt(const SptTree& tree, const SptInput& in, const EncodeSptOptions& o,
                      bool keep_map) {
  const std::size_t n = in.size(), total = tree.size();
  const NodeView v{tree, in, n};
  SptHeader h;
  h.flags = (o.full ? kSptFlagFull : 0u) | (in.colors.empty() ? 0u : kSptFlagColor);
  h.entry_bytes = o.full ? kSptFullEntryBytes : kSptCompactEntryBytes;
  h.depth = tree.depth;
  h.input_points = n;
  h.origin = o.origin;
  h.epsilon = o.epsilon;
  h.color_weight = o.color_weight;

  // Quantisation frame and scales.
  Vec3f lo = v.centre(0), hi = lo;
  float r_lo = INFINITY, r_hi = 0;
  for (std::size_t i = 0; i < total; ++i) {
    const Vec3f c = v.centre(i);
    lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
    hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
  }
  // r = e_g / epsilon, kept finite (a far outlier can push it past the float range).
  auto r_of = [&](float error) {
    return std::min(error / o.epsilon, std::numeric_limits<float>::max());
  };
  for (const SptDisc& d : tree.interiors)
    if (d.error > 0) {
      r_lo = std::min(r_lo, r_of(d.error));
      r_hi = std::max(r_hi, r_of(d.error));
    }
  if (!(r_lo <= r_hi)) r_lo = r_hi = 1;
  h.r_lo = r_lo;
  h.r_hi = r_hi;
  h.box_min = lo;
  h.step = {(hi.x - lo.x) / 65535.0f, (hi.y - lo.y) / 65535.0f, (hi.z - lo.z) / 65535.0f};
  // The decoded centre is within half a step per axis: the disc grows by that much.
  const float slack =
      o.full ? 0.0f
             : static_cast<float>(
                   0.5 * std::hypot(double(h.step.x), double(h.step.y), double(h.step.z)) * 1.0001);
  float d_lo = INFINITY, d_hi = 0;
  for (std::size_t i = 0; i < total; ++i) {
    const float d = 2 * v.radius(i);
    if (d > 0) {
      d_lo = std::min(d_lo, d + 2 * slack);
      d_hi = std::max(d_hi, d + 2 * slack);
    }
  }
  if (!(d_lo <= d_hi)) d_lo = d_hi = 1;
  h.d_lo = d_lo;
  h.d_hi = d_hi * 1.000001f;

  // r_min per node, as stored (a code, or the float itself).
  auto r_min_of = [&](std::size_t i) { return i < n ? 0.0f : r_of(tree.interiors[i - n].error); };
  std::vector<uint16_t> code;
  if (!o.full) {
    code.resize(total);
    tbb::parallel_for(std::size_t{0}, total,
                      [&](std::size_t i) { code[i] = encode_r(r_min_of(i), r_lo, r_hi); });
  }
  auto rmin_key = [&](std::size_t i) -> float { return o.full ? r_min_of(i) : code[i]; };
  auto rmax_key = [&](std::size_t i) -> float {
    const uint32_t p = tree.parent[i];
    if (p == kNoParent) return o.full ? INFINITY : kRInfinity;
    return rmin_key(p);
  };

  // Non-empty intervals, sorted by r_max descending, ties by node number: dest[i] is node i's
  // place in the list (kNoParent when left out). Entries are then encoded in node order and
  // scattered to their places (the node data is read in order, which is what keeps this fast).
  std::vector<uint32_t> dest(total, kNoParent);
  std::size_t kept = 0;
  if (o.full) {
    std::vector<uint32_t> order;
    for (std::size_t i = 0; i < total; ++i)
      if (rmax_key(i) > rmin_key(i)) order.push_back(static_cast<uint32_t>(i));
    tbb::parallel_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
      const float ka = rmax_key(a), kb = rmax_key(b);
      return ka != kb ? ka > kb : a < b;
    });
    for (std::size_t k = 0; k < order.size(); ++k) dest[order[k]] = static_cast<uint32_t>(k);
    kept = order.size();
  } else {  // counting sort on the 16-bit r_max code (stable: node order within a code)
    std::vector<uint32_t> next(65536, 0);
    auto bucket = [&](std::size_t i) { return 65535u - static_cast<uint32_t>(rmax_key(i)); };
    for (std::size_t i = 0; i < total; ++i)
      if (rmax_key(i) > rmin_key(i)) ++next[bucket(i)];
    uint32_t sum = 0;
    for (uint32_t& c : next) sum += std::exchange(c, sum);
    for (std::size_t i = 0; i < total; ++i)
      if (rmax_key(i) > rmin_key(i)) dest[i] = next[bucket(i)]++;
    kept = sum;
  }

  EncodedSpt out;
  out.entries = kept;
  out.dropped_empty = total - kept;
  h.entries = kept;
  out.bytes.resize(kSptHeaderBytes + kept * h.entry_bytes);
  unsigned char* base = out.bytes.data() + kSptHeaderBytes;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, total, 1 << 14), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      if (dest[i] == kNoParent) continue;
      unsigned char* e = base + std::size_t{dest[i]} * h.entry_bytes;
      const Vec3f c = v.centre(i), nn = v.normal(i);
      const std::array<uint8_t, 3> col =
          in.colors.empty() ? std::array<uint8_t, 3>{0, 0, 0} : v.color(i);
      if (o.full) {
        const float f[9] = {c.x,         c.y,        c.z, nn.x, nn.y, nn.z, 2 * v.radius(i),
                            rmin_key(i), rmax_key(i)};
        for (int j = 0; j < 9; ++j) put_f32(e + 4 * j, f[j]);
        e[36] = col[0];
        e[37] = col[1];
        e[38] = col[2];
        e[39] = 0;
      } else {
        put_u16(e, encode_position(c.x, lo.x, h.step.x));
        put_u16(e + 2, encode_position(c.y, lo.y, h.step.y));
        put_u16(e + 4, encode_position(c.z, lo.z, h.step.z));
        put_u16(e + 6, encode_normal(nn));
        const float d = v.radius(i) > 0 ? 2 * v.radius(i) + 2 * slack : 0.0f;
        put_u16(e + 8, encode_diameter(d, h.d_lo, h.d_hi));
        put_u16(e + 10, static_cast<uint16_t>(rmin_key(i)));
        put_u16(e + 12, static_cast<uint16_t>(rmax_key(i)));
        put_u16(e + 14, encode_rgb565(col));
      }
    }
  });
  write_spt_header(h, out.bytes.data());
  uint32_t crc = crc32c(0, out.bytes.data(), 124);
  crc = crc32c(crc, base, out.bytes.size() - kSptHeaderBytes);
  h.checksum = crc;
  write_spt_header(h, out.bytes.data());
  if (keep_map) {
    out.entry_of_node = std::move(dest);
  }
  return out;
}

}  // namespace splatkit::spt
