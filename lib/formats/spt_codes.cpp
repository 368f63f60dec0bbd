#include "formats/spt_codes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>

namespace splatkit::spt {

namespace {

void put_u64(unsigned char* p, uint64_t v) {
  put_u32(p, static_cast<uint32_t>(v));
  put_u32(p + 4, static_cast<uint32_t>(v >> 32));
}
uint64_t get_u64(const unsigned char* p) { return get_u32(p) | uint64_t{get_u32(p + 4)} << 32; }
void put_f64(unsigned char* p, double v) { put_u64(p, std::bit_cast<uint64_t>(v)); }
double get_f64(const unsigned char* p) { return std::bit_cast<double>(get_u64(p)); }

}  // namespace

void put_u32(unsigned char* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<unsigned char>(v >> (8 * i));
}
uint32_t get_u32(const unsigned char* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}
void put_f32(unsigned char* p, float v) { put_u32(p, std::bit_cast<uint32_t>(v)); }
float get_f32(const unsigned char* p) { return std::bit_cast<float>(get_u32(p)); }

void write_spt_header(const SptHeader& h, unsigned char* o) {
  std::memset(o, 0, kSptHeaderBytes);
  std::memcpy(o, kSptMagic, 8);
  put_u32(o + 8, h.version);
  put_u32(o + 12, h.flags);
  put_u32(o + 16, h.entry_bytes);
  put_u32(o + 20, h.depth);
  put_u64(o + 24, h.entries);
  put_u64(o + 32, h.input_points);
  for (int i = 0; i < 3; ++i) put_f64(o + 40 + 8 * i, h.origin[i]);
  const float f[10] = {h.box_min.x, h.box_min.y, h.box_min.z, h.step.x, h.step.y,
                       h.step.z,    h.r_lo,      h.r_hi,      h.d_lo,   h.d_hi};
  for (int i = 0; i < 10; ++i) put_f32(o + 64 + 4 * i, f[i]);
  put_f32(o + 104, h.epsilon);
  put_f32(o + 108, h.color_weight);
  put_u32(o + 124, h.checksum);  // 112..123 reserved, zero
}

SptHeader read_spt_header(const unsigned char* in) {
  SptHeader h;
  h.version = get_u32(in + 8);
  h.flags = get_u32(in + 12);
  h.entry_bytes = get_u32(in + 16);
  h.depth = get_u32(in + 20);
  h.entries = get_u64(in + 24);
  h.input_points = get_u64(in + 32);
  for (int i = 0; i < 3; ++i) h.origin[i] = get_f64(in + 40 + 8 * i);
  h.box_min = {get_f32(in + 64), get_f32(in + 68), get_f32(in + 72)};
  h.step = {get_f32(in + 76), get_f32(in + 80), get_f32(in + 84)};
  h.r_lo = get_f32(in + 88);
  h.r_hi = get_f32(in + 92);
  h.d_lo = get_f32(in + 96);
  h.d_hi = get_f32(in + 100);
  h.epsilon = get_f32(in + 104);
  h.color_weight = get_f32(in + 108);
  h.checksum = get_u32(in + 124);
  return h;
}

float decode_position(uint16_t q, float lo, float step) {
  return lo + static_cast<float>(q) * step;
}

uint16_t encode_normal(const Vec3f& n) {
  const float s = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
  float u = n.x / s, v = n.y / s;
  if (n.z < 0) {
    const float uu = (1 - std::fabs(v)) * (u >= 0 ? 1.0f : -1.0f);
    v = (1 - std::fabs(u)) * (v >= 0 ? 1.0f : -1.0f);
    u = uu;
  }
  auto q = [](float x) {
    return static_cast<uint16_t>(
        std::clamp(std::floor((x * 0.5f + 0.5f) * 255.0f + 0.5f), 0.0f, 255.0f));
  };
  return static_cast<uint16_t>(q(u) | q(v) << 8);
}

Vec3f decode_normal(uint16_t code) {
  const float u = (code & 0xFF) / 255.0f * 2 - 1, v = (code >> 8) / 255.0f * 2 - 1;
  Vec3f n{u, v, 1 - std::fabs(u) - std::fabs(v)};
  if (n.z < 0) {
    const float x = (1 - std::fabs(n.y)) * (n.x >= 0 ? 1.0f : -1.0f);
    n.y = (1 - std::fabs(n.x)) * (n.y >= 0 ? 1.0f : -1.0f);
    n.x = x;
  }
  return normalized(n);
}

LogScale::LogScale(double l, double h, int n) : lo(l), hi(h), steps(n) {
  if (h > l) {
    to_position = (n - 1) / std::log(h / l);
    to_value = std::log(h / l) / (n - 1);
  }
}
double LogScale::position(double v) const { return hi > lo ? std::log(v / lo) * to_position : 0.0; }
double LogScale::value(double pos) const { return hi > lo ? lo * std::exp(pos * to_value) : lo; }

LogScale r_scale(float r_lo, float r_hi) { return {r_lo, r_hi, 65534}; }
LogScale d_scale(float d_lo, float d_hi) { return {d_lo, d_hi, 65535}; }

uint16_t encode_r(float r, const LogScale& s) {
  if (std::isinf(r)) return kRInfinity;
  if (!(r > 0)) return 0;
  const float lo = static_cast<float>(s.lo), hi = static_cast<float>(s.hi);
  const double pos = std::floor(s.position(std::clamp(r, lo, hi)) + 0.5);
  return static_cast<uint16_t>(1 + std::clamp(pos, 0.0, 65533.0));
}
float decode_r(uint16_t code, const LogScale& s) {
  if (code == 0) return 0;
  if (code == kRInfinity) return INFINITY;
  return static_cast<float>(s.value(code - 1));
}

namespace {

// The smallest code from the logarithm's estimate on whose diameter (decoded(code)) is >= d.
template <class Decoded>
uint16_t diameter_code(float d, const LogScale& s, Decoded decoded) {
  if (!(d > 0)) return 0;
  const float lo = static_cast<float>(s.lo);
  double pos = std::ceil(s.position(std::max(d, lo)) - 1e-9);
  pos = std::clamp(pos, 0.0, 65534.0);
  while (pos < 65534 && decoded(static_cast<uint16_t>(1 + pos)) < d) ++pos;
  return static_cast<uint16_t>(1 + pos);
}

}  // namespace

uint16_t encode_diameter(float d, const LogScale& s) {
  return diameter_code(d, s, [&](uint16_t code) { return decode_diameter(code, s); });
}

DiameterCoder::DiameterCoder(const LogScale& s) : scale_(s), decoded_(65536) {
  for (std::size_t code = 0; code < decoded_.size(); ++code)
    decoded_[code] = decode_diameter(static_cast<uint16_t>(code), s);
}

uint16_t DiameterCoder::encode(float d) const {
  return diameter_code(d, scale_, [&](uint16_t code) { return decoded_[code]; });
}

float decode_diameter(uint16_t code, const LogScale& s) {
  if (code == 0) return 0;
  return static_cast<float>(s.value(code - 1));
}

bool looks_like_spt(std::string_view head) {
  return head.size() >= 8 && std::memcmp(head.data(), kSptMagic, 8) == 0;
}

}  // namespace splatkit::spt
