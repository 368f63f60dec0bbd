#include "formats/read_spt.h"

#include <cmath>
#include <cstring>

#include "splatkit/crc32c.h"
#include "splatkit/error.h"

namespace splatkit {

namespace {

using namespace spt;

[[noreturn]] void fail(const std::string& name, uint64_t at, const std::string& what) {
  throw_bad_input(name, "byte " + std::to_string(at) + ": " + what);
}

bool finite3(const Vec3f& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check_header(std::span<const unsigned char> b, const SptHeader& h, const std::string& name) {
  if (h.version == 0) fail(name, 8, "version 0 does not exist");
  if (h.version > kSptVersion)
    throw_unsupported(name, "byte 8: .spt version " + std::to_string(h.version) +
                                " is newer than this reader (it reads versions up to " +
                                std::to_string(kSptVersion) + ")");
  if (h.flags & ~kSptKnownFlags)
    throw_unsupported(name,
                      "byte 12: unknown flag bits " + std::to_string(h.flags & ~kSptKnownFlags));
  const uint32_t want = h.full() ? kSptFullEntryBytes : kSptCompactEntryBytes;
  if (h.entry_bytes != want)
    fail(name, 16,
         "entry size " + std::to_string(h.entry_bytes) + " (the flags say " + std::to_string(want) +
             ")");
  for (int i = 112; i < 124; ++i)
    if (b[i] != 0) fail(name, static_cast<uint64_t>(i), "reserved header byte is not zero");
  const uint64_t left = b.size() - kSptHeaderBytes;
  if (h.entries > left / h.entry_bytes)
    fail(name, 24,
         std::to_string(h.entries) + " entries need more than the " + std::to_string(left) +
             " bytes after the header (truncated file?)");
  if (h.entries * h.entry_bytes != left)
    fail(name, kSptHeaderBytes + h.entries * h.entry_bytes,
         std::to_string(left - h.entries * h.entry_bytes) + " bytes after the last entry");
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(h.origin[i]))
      fail(name, 40 + 8 * static_cast<uint64_t>(i), "origin is not finite");
  if (!finite3(h.box_min)) fail(name, 64, "quantisation frame is not finite");
  if (!finite3(h.step) || h.step.x < 0 || h.step.y < 0 || h.step.z < 0)
    fail(name, 76, "quantisation step is negative or not finite");
  if (!(h.r_lo > 0) || !(h.r_hi >= h.r_lo) || !std::isfinite(h.r_hi))
    fail(name, 88, "r scale is not 0 < r_lo <= r_hi < infinity");
  if (!(h.d_lo > 0) || !(h.d_hi >= h.d_lo) || !std::isfinite(h.d_hi))
    fail(name, 96, "diameter scale is not 0 < d_lo <= d_hi < infinity");
  if (!(h.epsilon > 0) || !std::isfinite(h.epsilon)) fail(name, 104, "epsilon is not positive");
  if (!(h.color_weight >= 0) || !std::isfinite(h.color_weight))
    fail(name, 108, "colour weight is negative or not finite");
}

}  // namespace

SptModel parse_spt(std::span<const unsigned char> b, const std::string& name) {
  if (b.size() < 8 || std::memcmp(b.data(), kSptMagic, 8) != 0)
    fail(name, 0, "not an .spt file (bad magic)");
  if (b.size() < kSptHeaderBytes)
    fail(name, b.size(), "truncated header (" + std::to_string(b.size()) + " of 128 bytes)");
  SptModel m;
  m.header = read_spt_header(b.data());
  const SptHeader& h = m.header;
  check_header(b, h, name);
  uint32_t crc = crc32c(0, b.data(), 124);
  crc = crc32c(crc, b.data() + kSptHeaderBytes, b.size() - kSptHeaderBytes);
  if (crc != h.checksum) fail(name, 124, "checksum mismatch (the file is damaged)");
  m.file_bytes = b.size();
  const std::size_t n = static_cast<std::size_t>(h.entries);
  m.positions.resize(n);
  m.normals.resize(n);
  m.diameters.resize(n);
  m.r_min.resize(n);
  m.r_max.resize(n);
  if (h.has_color()) m.colors.resize(n);
  float previous = INFINITY;
  const LogScale rs = r_scale(h.r_lo, h.r_hi), ds = d_scale(h.d_lo, h.d_hi);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char* e = b.data() + kSptHeaderBytes + i * h.entry_bytes;
    const uint64_t at = kSptHeaderBytes + i * uint64_t{h.entry_bytes};
    SptEntry x;
    if (h.full()) {
      x.position = {get_f32(e), get_f32(e + 4), get_f32(e + 8)};
      x.normal = {get_f32(e + 12), get_f32(e + 16), get_f32(e + 20)};
      x.diameter = get_f32(e + 24);
      x.r_min = get_f32(e + 28);
      x.r_max = get_f32(e + 32);
      x.color = {e[36], e[37], e[38]};
      if (!finite3(x.position)) fail(name, at, "position is not finite");
      const float len = norm(x.normal);
      if (!std::isfinite(len) || std::fabs(len - 1) > 1e-3f)
        fail(name, at + 12, "normal is not unit");
      if (!(x.diameter >= 0) || !std::isfinite(x.diameter))
        fail(name, at + 24, "diameter is negative or not finite");
      if (!(x.r_min >= 0) || !std::isfinite(x.r_min))
        fail(name, at + 28, "r_min is negative or not finite");
      if (!(x.r_max >= x.r_min)) fail(name, at + 32, "r_max is below r_min");
    } else {
      for (int k = 0; k < 3; ++k) {
        const float lo = (&h.box_min.x)[k], step = (&h.step.x)[k];
        (&x.position.x)[k] = decode_position(get_u16(e + 2 * k), lo, step);
      }
      x.normal = decode_normal(get_u16(e + 6));
      x.diameter = decode_diameter(get_u16(e + 8), ds);
      const uint16_t rmin = get_u16(e + 10), rmax = get_u16(e + 12);
      if (rmin == kRInfinity) fail(name, at + 10, "r_min is infinite");
      if (rmax < rmin) fail(name, at + 12, "r_max is below r_min");
      x.r_min = decode_r(rmin, rs);
      x.r_max = decode_r(rmax, rs);
      x.color = decode_rgb565(get_u16(e + 14));
      if (!finite3(x.position)) fail(name, at, "position is not finite");
    }
    if (x.r_max > previous) fail(name, at, "entries not sorted by r_max descending");
    previous = x.r_max;
    m.positions[i] = x.position;
    m.normals[i] = x.normal;
    m.diameters[i] = x.diameter;
    m.r_min[i] = x.r_min;
    m.r_max[i] = x.r_max;
    if (h.has_color()) m.colors[i] = x.color;
    m.leaves += x.r_min == 0;
  }
  return m;
}

SptModel read_spt(InputStream& in) {
  std::vector<unsigned char> bytes;
  if (in.size_hint()) bytes.reserve(*in.size_hint());
  unsigned char buf[1 << 16];
  for (std::size_t n; (n = in.read_some(buf, sizeof buf)) > 0;)
    bytes.insert(bytes.end(), buf, buf + n);
  return parse_spt(bytes, in.name());
}

}  // namespace splatkit
