// LASzip's layered chunks (compressor 3) of point data formats 6-8: the version 3 models POINT14,
// RGB14, RGBNIR14 and BYTE14 ([Isenburg13] and LASzip's LAS 1.4 extension). Layout and models:
// formats/laz.md, "Layered chunks".
//
// A chunk is: the first record raw; the chunk's point count (uint32); the byte size of every
// layer (uint32 each, in item order: POINT14's nine, RGB14's one, RGBNIR14's two, BYTE14's one
// per byte); then the layers' bytes in the same order. Every layer is its own arithmetic-coded
// stream. A layer other than POINT14's X/Y and Z layers may be empty (size 0): its field had the
// same value in every point of the chunk.
//
// Every model set exists once per scanner channel (a "context", 0-3); the POINT14 coder switches
// context when a point's channel differs from the previous point's, and the other items follow.
// Records are LAS 1.4 point records (format 6: 30 bytes, then RGB, NIR, extra bytes).
#include <array>
#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "formats/laz_chunk.h"
#include "formats/laz_gps_time.h"
#include "formats/laz_models.h"
#include "formats/little_endian.h"

namespace splatkit::laz {

namespace {

using le::get16;
using le::get32;
using le::get64;
using le::put16;
using le::put32;
using le::put64;

// Contexts of the X/Y medians and of Z by number of returns n and return number r (LASzip's
// tables for LAS 1.4's 4-bit counts: 6 and 8 classes).
constexpr uint8_t kMap6[16][16] = {{0, 1, 2, 3, 4, 5, 3, 4, 4, 5, 5, 5, 5, 5, 5, 5},
                                   {1, 0, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3, 3},
                                   {2, 1, 2, 4, 4, 4, 4, 4, 4, 4, 4, 3, 3, 3, 3, 3},
                                   {3, 3, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
                                   {4, 3, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
                                   {5, 3, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4},
                                   {3, 3, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4, 4},
                                   {4, 3, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4, 4},
                                   {4, 3, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4, 4},
                                   {5, 3, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4, 4},
                                   {5, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 4, 4, 4, 4, 4},
                                   {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 4, 4, 4},
                                   {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4, 4},
                                   {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5, 4},
                                   {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5, 5},
                                   {5, 3, 3, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 4, 5, 5}};
// |n - r| capped at 7.
constexpr uint8_t level8(unsigned n, unsigned r) {
  const unsigned d = n > r ? n - r : r - n;
  return static_cast<uint8_t>(d < 7 ? d : 7);
}

// A fixed array of models of `Symbols` symbols, each created on first use.
template <std::size_t N, uint32_t Symbols>
struct LazyArray {
  std::array<std::unique_ptr<SymbolModel>, N> m;
  SymbolModel& operator[](std::size_t i) {
    if (!m[i]) m[i] = std::make_unique<SymbolModel>(Symbols);
    return *m[i];
  }
};

// One layer's encoder and its bytes.
struct Layer {
  std::vector<unsigned char> bytes;
  ArithmeticEncoder enc{bytes};
  bool changed = false;
};

// One layer's decoder, over the layer's bytes (absent when the layer is empty).
struct InLayer {
  std::unique_ptr<ArithmeticDecoder> dec;
  void open(const unsigned char* p, uint32_t size) {
    if (size == 0) return;
    dec = std::make_unique<ArithmeticDecoder>(p, p + size);
    dec->init();
  }
  explicit operator bool() const { return dec != nullptr; }
};

// POINT14 record fields (LAS 1.4 R15 table 15).
constexpr std::size_t kPoint14Size = 30;
unsigned ret_of(const unsigned char* p) { return p[14] & 15; }
unsigned nret_of(const unsigned char* p) { return p[14] >> 4; }
unsigned channel_of(const unsigned char* p) { return (p[15] >> 4) & 3; }
// Classification flags, scan direction and edge of flight line as LASzip's 6-bit symbol.
unsigned flags_of(const unsigned char* p) { return (p[15] & 0x0F) | ((p[15] >> 2) & 0x30); }
void set_flags(unsigned char* p, unsigned flags, unsigned channel) {
  p[15] = static_cast<unsigned char>((flags & 0x0F) | ((flags & 0x30) << 2) | (channel << 4));
}

// The models and last values of one scanner channel.
struct Point14Context {
  explicit Point14Context(const unsigned char* item) {
    gps.set_first(static_cast<int64_t>(get64(item + 22)));
    std::memcpy(last, item, kPoint14Size);
    last_z.fill(static_cast<int32_t>(get32(item + 8)));
    last_intensity.fill(get16(item + 12));
  }

  // The fields of the layers after Z (intensity to GPS time) as a new context takes them from
  // `item` (Point14::decode_layers: the X/Y pass made this context before they were decoded; the
  // Z pass sets its Z values itself).
  void take_rest(const unsigned char* item) {
    std::memcpy(last + 12, item + 12, 2);   // intensity
    std::memcpy(last + 15, item + 15, 15);  // flags to GPS time
    gps = GpsTimeModel<false>();
    gps.set_first(static_cast<int64_t>(get64(item + 22)));
    last_intensity.fill(get16(item + 12));
  }

  unsigned char last[kPoint14Size];
  bool last_gps_change = false;
  std::array<SymbolModel, 8> changed_values{SymbolModel(128), SymbolModel(128), SymbolModel(128),
                                            SymbolModel(128), SymbolModel(128), SymbolModel(128),
                                            SymbolModel(128), SymbolModel(128)};
  SymbolModel scanner_channel{3};
  LazyArray<16, 16> number_of_returns, return_number;
  SymbolModel return_number_gps_same{13};
  IntegerCompressor ic_dx{32, 2}, ic_dy{32, 22}, ic_z{32, 20};
  std::array<Median5, 12> median_x{}, median_y{};
  std::array<int32_t, 8> last_z{};
  LazyArray<64, 256> classification, user_data;
  LazyArray<64, 64> flags;
  IntegerCompressor ic_intensity{16, 4};
  std::array<uint16_t, 8> last_intensity{};
  IntegerCompressor ic_scan_angle{16, 2}, ic_point_source{16, 1};
  GpsTimeModel<false> gps;  // version 3 (laz_gps_time.h)
};

// POINT14 version 3: nine layers (X/Y with the change bits, Z, classification, flags, intensity,
// scan angle, user data, point source, GPS time).
class Point14 {
 public:
  static constexpr int kLayers = 9;
  enum { kXY, kZ, kClass, kFlags, kIntensity, kAngle, kUser, kSource, kGps };

  // The chunk's first record; returns its scanner channel (the other items' context).
  unsigned init(const unsigned char* item) {
    current_ = channel_of(item);
    ctx_[current_] = std::make_unique<Point14Context>(item);
    return current_;
  }

  void open(const unsigned char* p, const uint32_t* sizes) {
    for (int i = 0; i < kLayers; ++i) {
      in_[i].open(p, sizes[i]);
      p += sizes[i];
    }
    if (!in_[kXY] || !in_[kZ]) throw LazDataError("the X/Y or Z layer of POINT14 is empty");
  }

  // What the X/Y layer of a record tells the later layers (decode_rest).
  struct XyInfo {
    uint8_t channel;  // the scanner channel after this record's switch, if any
    uint8_t fresh;    // 1: the switch made that channel's context
    uint8_t returns;  // r | n << 4
    uint8_t changed;  // the change bits
    uint8_t z_k;      // the Z compressor's context from the X/Y compressors' k
  };

  // The layers of the records 1..count-1 at out + i * rl, one layer after another over the
  // chunk: X/Y first (which gives `contexts[i]`, the other items' context), then Z, then
  // intensity to GPS time; the same records as decoding each record's layers in turn (the layers
  // are separate streams), with each decoder's models and branches hot.
  void decode_layers(unsigned char* out, uint64_t count, std::size_t rl, uint8_t* contexts) {
    std::vector<XyInfo> info(count);
    const unsigned first = current_;
    for (uint64_t i = 1; i < count; ++i)
      contexts[i] = static_cast<uint8_t>(decode_xy(out + i * rl, info[i]));
    unsigned channel = first;
    for (uint64_t i = 1; i < count; ++i) {
      const XyInfo& x = info[i];
      // A new context's last Z values are the previous channel's last Z, as it is now.
      if (x.fresh)
        ctx_[x.channel]->last_z.fill(static_cast<int32_t>(get32(ctx_[channel]->last + 8)));
      channel = x.channel;
      decode_z(out + i * rl, x);
    }
    channel = first;
    for (uint64_t i = 1; i < count; ++i) {
      const XyInfo& x = info[i];
      if (x.fresh) ctx_[x.channel]->take_rest(ctx_[channel]->last);
      channel = x.channel;
      decode_rest(out + i * rl, x);
    }
  }

  // The Z layer of one record (its channel's context made current by decode_layers).
  void decode_z(unsigned char* item, const XyInfo& x) {
    Point14Context* c = ctx_[x.channel].get();
    const unsigned n = x.returns >> 4, l = level8(n, x.returns & 15u);
    c->last_z[l] = c->ic_z.decompress(*in_[kZ].dec, c->last_z[l], (n == 1) + x.z_k);
    put32(c->last + 8, static_cast<uint32_t>(c->last_z[l]));
    put32(item + 8, static_cast<uint32_t>(c->last_z[l]));
  }

  // The X/Y layer of one record: the change bits, the scanner channel, the returns, X and Y.
  // Returns the other items' context for the record. As in LASzip (and therefore in every file),
  // that is the new scanner channel when this point switched channel and 0 otherwise, not the
  // current channel.
  unsigned decode_xy(unsigned char* item, XyInfo& info) {
    ArithmeticDecoder xy = *in_[kXY].dec;
    Point14Context* c = ctx_[current_].get();
    const unsigned char* prev = c->last;
    const unsigned lpr =
        (ret_of(prev) == 1) | (ret_of(prev) >= nret_of(prev)) << 1 | c->last_gps_change << 2;
    const uint32_t changed = xy.decode_symbol(c->changed_values[lpr]);
    info.fresh = 0;
    if (changed & 64) {
      const unsigned channel = (current_ + xy.decode_symbol(c->scanner_channel) + 1) & 3;
      if (!ctx_[channel]) {
        ctx_[channel] = std::make_unique<Point14Context>(c->last);
        info.fresh = 1;
      }
      current_ = channel;
      c = ctx_[channel].get();
    }
    unsigned char* rec = c->last;
    const unsigned last_n = nret_of(rec), last_r = ret_of(rec);
    const bool gps_change = (changed & 16) != 0;
    unsigned n = last_n, r = last_r;
    if (changed & 4) n = xy.decode_symbol(c->number_of_returns[last_n]);
    switch (changed & 3) {
      case 1:
        r = (last_r + 1) & 15;
        break;
      case 2:
        r = (last_r + 15) & 15;
        break;
      case 3:
        r = gps_change ? xy.decode_symbol(c->return_number[last_r])
                       : (last_r + xy.decode_symbol(c->return_number_gps_same) + 2) & 15;
        break;
      default:
        break;
    }
    rec[14] = static_cast<unsigned char>(r | n << 4);
    const unsigned m = kMap6[n][r];
    const unsigned mctx = m << 1 | gps_change;
    int32_t diff = c->ic_dx.decompress(xy, c->median_x[mctx].get(), n == 1);
    put32(rec, static_cast<uint32_t>(wrap_add(static_cast<int32_t>(get32(rec)), diff)));
    c->median_x[mctx].add(diff);
    uint32_t k = c->ic_dx.k();
    diff = c->ic_dy.decompress(xy, c->median_y[mctx].get(), (n == 1) + (k < 20 ? k & ~1u : 20));
    put32(rec + 4, static_cast<uint32_t>(wrap_add(static_cast<int32_t>(get32(rec + 4)), diff)));
    c->median_y[mctx].add(diff);
    k = (c->ic_dx.k() + c->ic_dy.k()) / 2;
    c->last_gps_change = gps_change;
    info.channel = static_cast<uint8_t>(current_);
    info.returns = rec[14];
    info.changed = static_cast<uint8_t>(changed);
    info.z_k = static_cast<uint8_t>(k < 18 ? k & ~1u : 18);
    std::memcpy(item, rec, 8);
    item[14] = rec[14];
    *in_[kXY].dec = xy;
    return (changed & 64) ? current_ : 0;
  }

  // The layers after Z of one record (its channel's context made current by decode_layers).
  void decode_rest(unsigned char* item, const XyInfo& x) {
    Point14Context* c = ctx_[x.channel].get();
    unsigned char* rec = c->last;
    const unsigned n = x.returns >> 4, r = x.returns & 15u;
    const bool gps_change = (x.changed & 16) != 0;
    const unsigned cpr = (r == 1) | (r >= n) << 1;
    if (in_[kClass])
      rec[16] = static_cast<unsigned char>(
          in_[kClass].dec->decode_symbol(c->classification[((rec[16] & 0x1Fu) << 1) + (cpr == 3)]));
    unsigned flags = flags_of(rec);
    if (in_[kFlags]) flags = in_[kFlags].dec->decode_symbol(c->flags[flags]);
    set_flags(rec, flags, x.channel);
    if (in_[kIntensity]) {
      uint16_t& li = c->last_intensity[cpr << 1 | gps_change];
      li = static_cast<uint16_t>(c->ic_intensity.decompress(*in_[kIntensity].dec, li, cpr));
      put16(rec + 12, li);
    }
    if (in_[kAngle] && (x.changed & 8))
      put16(rec + 18, static_cast<uint32_t>(c->ic_scan_angle.decompress(
                          *in_[kAngle].dec, static_cast<int16_t>(get16(rec + 18)), gps_change)));
    if (in_[kUser])
      rec[17] =
          static_cast<unsigned char>(in_[kUser].dec->decode_symbol(c->user_data[rec[17] / 4u]));
    if (in_[kSource] && (x.changed & 32))
      put16(rec + 20, static_cast<uint32_t>(
                          c->ic_point_source.decompress(*in_[kSource].dec, get16(rec + 20), 0)));
    if (in_[kGps] && gps_change)
      put64(rec + 22, static_cast<uint64_t>(c->gps.decode(*in_[kGps].dec)));
    std::memcpy(item + 12, rec + 12, 2);
    std::memcpy(item + 15, rec + 15, 15);
  }

  unsigned encode(const unsigned char* item) {
    Point14Context* c = ctx_[current_].get();
    const unsigned char* prev = c->last;
    const unsigned lpr =
        (ret_of(prev) == 1) | (ret_of(prev) >= nret_of(prev)) << 1 | c->last_gps_change << 2;
    const unsigned channel = channel_of(item);
    // Changes are relative to the last point of the item's own channel when it has one.
    const unsigned char* last = channel != current_ && ctx_[channel] ? ctx_[channel]->last : prev;
    const bool source_change = get16(item + 20) != get16(last + 20);
    const bool gps_change = get64(item + 22) != get64(last + 22);
    const bool angle_change = get16(item + 18) != get16(last + 18);
    const unsigned last_n = nret_of(last), last_r = ret_of(last);
    const unsigned n = nret_of(item), r = ret_of(item);
    uint32_t changed = (channel != current_) << 6 | source_change << 5 | gps_change << 4 |
                       angle_change << 3 | (n != last_n) << 2;
    if (r != last_r) changed |= r == ((last_r + 1) & 15) ? 1 : r == ((last_r + 15) & 15) ? 2 : 3;
    Layer& xy = out_[kXY];
    xy.enc.encode_symbol(c->changed_values[lpr], changed);
    if (changed & 64) {
      xy.enc.encode_symbol(c->scanner_channel, (channel - current_ + 3) & 3);
      if (!ctx_[channel]) ctx_[channel] = std::make_unique<Point14Context>(c->last);
      current_ = channel;
      c = ctx_[channel].get();
    }
    unsigned char* rec = c->last;
    if (changed & 4) xy.enc.encode_symbol(c->number_of_returns[last_n], n);
    if ((changed & 3) == 3) {
      if (gps_change)
        xy.enc.encode_symbol(c->return_number[last_r], r);
      else
        xy.enc.encode_symbol(c->return_number_gps_same, (r - last_r + 14) & 15);
    }
    const unsigned m = kMap6[n][r], l = level8(n, r);
    const unsigned cpr = (r == 1) | (r >= n) << 1;
    const unsigned mctx = m << 1 | gps_change;
    int32_t diff = wrap_sub(static_cast<int32_t>(get32(item)), static_cast<int32_t>(get32(rec)));
    c->ic_dx.compress(xy.enc, c->median_x[mctx].get(), diff, n == 1);
    c->median_x[mctx].add(diff);
    uint32_t k = c->ic_dx.k();
    diff = wrap_sub(static_cast<int32_t>(get32(item + 4)), static_cast<int32_t>(get32(rec + 4)));
    c->ic_dy.compress(xy.enc, c->median_y[mctx].get(), diff, (n == 1) + (k < 20 ? k & ~1u : 20));
    c->median_y[mctx].add(diff);
    k = (c->ic_dx.k() + c->ic_dy.k()) / 2;
    const int32_t z = static_cast<int32_t>(get32(item + 8));
    c->ic_z.compress(out_[kZ].enc, c->last_z[l], z, (n == 1) + (k < 18 ? k & ~1u : 18));
    c->last_z[l] = z;
    out_[kClass].changed |= item[16] != rec[16];
    out_[kClass].enc.encode_symbol(c->classification[((rec[16] & 0x1Fu) << 1) + (cpr == 3)],
                                   item[16]);
    const unsigned flags = flags_of(item), last_flags = flags_of(rec);
    out_[kFlags].changed |= flags != last_flags;
    out_[kFlags].enc.encode_symbol(c->flags[last_flags], flags);
    const uint16_t intensity = get16(item + 12);
    out_[kIntensity].changed |= intensity != get16(rec + 12);
    uint16_t& li = c->last_intensity[cpr << 1 | gps_change];
    c->ic_intensity.compress(out_[kIntensity].enc, li, intensity, cpr);
    li = intensity;
    if (angle_change) {
      out_[kAngle].changed = true;
      c->ic_scan_angle.compress(out_[kAngle].enc, static_cast<int16_t>(get16(rec + 18)),
                                static_cast<int16_t>(get16(item + 18)), gps_change);
    }
    out_[kUser].changed |= item[17] != rec[17];
    out_[kUser].enc.encode_symbol(c->user_data[rec[17] / 4u], item[17]);
    if (source_change) {
      out_[kSource].changed = true;
      c->ic_point_source.compress(out_[kSource].enc, get16(rec + 20), get16(item + 20), 0);
    }
    if (gps_change) {
      out_[kGps].changed = true;
      c->gps.encode(out_[kGps].enc, static_cast<int64_t>(get64(item + 22)));
    }
    std::memcpy(rec, item, kPoint14Size);
    c->last_gps_change = gps_change;
    return (changed & 64) ? current_ : 0;
  }

  Layer* layers() { return out_; }

 private:
  unsigned current_ = 0;
  std::array<std::unique_ptr<Point14Context>, 4> ctx_;
  InLayer in_[kLayers];
  Layer out_[kLayers];
};

// RGB14 (3 values, one layer) and RGBNIR14 (4 values; RGB and NIR layers), version 3. Note that
// LASzip's version 3 keeps comparing with the previous channel's last colour for the first point
// after a switch to a channel already seen (and stores that point's colour there); files carry
// that, so both directions here do the same.
class Rgb14 {
 public:
  explicit Rgb14(bool nir) : nir_(nir) {}
  int layers() const { return nir_ ? 2 : 1; }
  std::size_t size() const { return nir_ ? 8 : 6; }

  void init(const unsigned char* item, unsigned context) {
    current_ = context;
    ctx_[context] = std::make_unique<Context>(item, nir_ ? 4 : 3);
  }
  void open(const unsigned char* p, const uint32_t* sizes) {
    rgb_.open(p, sizes[0]);
    if (nir_) nir_in_.open(p + sizes[0], sizes[1]);
  }

  void decode(unsigned char* item, unsigned context) {
    uint16_t* last = switch_context(context);
    Context& c = *ctx_[current_];
    uint32_t v[4] = {last[0], last[1], last[2], last[3]};
    if (rgb_) {
      ArithmeticDecoder dec = *rgb_.dec;  // a local for the record, as in Point14::decode
      const uint32_t sym = dec.decode_symbol(c.byte_used);
      v[0] =
          (sym & 1) ? ((dec.decode_symbol(c.diff[0]) + (last[0] & 0xFF)) & 0xFF) : (last[0] & 0xFF);
      v[0] |= (sym & 2) ? ((dec.decode_symbol(c.diff[1]) + (last[0] >> 8)) & 0xFF) << 8
                        : (last[0] & 0xFF00);
      if (sym & 64) {
        int d = static_cast<int>(v[0] & 0xFF) - static_cast<int>(last[0] & 0xFF);
        v[1] = (sym & 4) ? ((dec.decode_symbol(c.diff[2]) + clamp_u8(d + (last[1] & 0xFF))) & 0xFF)
                         : (last[1] & 0xFF);
        if (sym & 16) {
          d = (d + static_cast<int>(v[1] & 0xFF) - static_cast<int>(last[1] & 0xFF)) / 2;
          v[2] = (dec.decode_symbol(c.diff[4]) + clamp_u8(d + (last[2] & 0xFF))) & 0xFF;
        } else {
          v[2] = last[2] & 0xFF;
        }
        d = static_cast<int>(v[0] >> 8) - static_cast<int>(last[0] >> 8);
        v[1] |= (sym & 8)
                    ? ((dec.decode_symbol(c.diff[3]) + clamp_u8(d + (last[1] >> 8))) & 0xFF) << 8
                    : (last[1] & 0xFF00);
        if (sym & 32) {
          d = (d + static_cast<int>(v[1] >> 8) - static_cast<int>(last[1] >> 8)) / 2;
          v[2] |= ((dec.decode_symbol(c.diff[5]) + clamp_u8(d + (last[2] >> 8))) & 0xFF) << 8;
        } else {
          v[2] |= last[2] & 0xFF00;
        }
      } else {
        v[1] = v[2] = v[0];
      }
      *rgb_.dec = dec;
    }
    if (nir_ && nir_in_) {
      ArithmeticDecoder& dec = *nir_in_.dec;
      const uint32_t sym = dec.decode_symbol(c.nir_used);
      uint32_t lo = last[3] & 0xFF, hi = last[3] >> 8;
      if (sym & 1) lo = (dec.decode_symbol(c.nir_diff[0]) + lo) & 0xFF;
      if (sym & 2) hi = (dec.decode_symbol(c.nir_diff[1]) + hi) & 0xFF;
      v[3] = lo | hi << 8;
    }
    for (int i = 0; i < (nir_ ? 4 : 3); ++i) {
      last[i] = static_cast<uint16_t>(v[i]);
      put16(item + 2 * i, v[i]);
    }
  }

  void encode(const unsigned char* item, unsigned context) {
    uint16_t* last = switch_context(context);
    Context& c = *ctx_[current_];
    uint32_t v[4] = {};
    for (int i = 0; i < (nir_ ? 4 : 3); ++i) v[i] = get16(item + 2 * i);
    uint32_t sym =
        ((last[0] & 0xFF) != (v[0] & 0xFF)) << 0 | ((last[0] & 0xFF00) != (v[0] & 0xFF00)) << 1 |
        ((last[1] & 0xFF) != (v[1] & 0xFF)) << 2 | ((last[1] & 0xFF00) != (v[1] & 0xFF00)) << 3 |
        ((last[2] & 0xFF) != (v[2] & 0xFF)) << 4 | ((last[2] & 0xFF00) != (v[2] & 0xFF00)) << 5;
    sym |= (v[0] != v[1] || v[0] != v[2]) << 6;
    ArithmeticEncoder& enc = rgb_out_.enc;
    enc.encode_symbol(c.byte_used, sym);
    rgb_out_.changed |= sym != 0;
    int diff_l = 0, diff_h = 0;
    if (sym & 1) {
      diff_l = static_cast<int>(v[0] & 0xFF) - static_cast<int>(last[0] & 0xFF);
      enc.encode_symbol(c.diff[0], static_cast<uint32_t>(diff_l) & 0xFF);
    }
    if (sym & 2) {
      diff_h = static_cast<int>(v[0] >> 8) - static_cast<int>(last[0] >> 8);
      enc.encode_symbol(c.diff[1], static_cast<uint32_t>(diff_h) & 0xFF);
    }
    if (sym & 64) {
      if (sym & 4) {
        const int corr =
            static_cast<int>(v[1] & 0xFF) - static_cast<int>(clamp_u8(diff_l + (last[1] & 0xFF)));
        enc.encode_symbol(c.diff[2], static_cast<uint32_t>(corr) & 0xFF);
      }
      if (sym & 16) {
        diff_l = (diff_l + static_cast<int>(v[1] & 0xFF) - static_cast<int>(last[1] & 0xFF)) / 2;
        const int corr =
            static_cast<int>(v[2] & 0xFF) - static_cast<int>(clamp_u8(diff_l + (last[2] & 0xFF)));
        enc.encode_symbol(c.diff[4], static_cast<uint32_t>(corr) & 0xFF);
      }
      if (sym & 8) {
        const int corr =
            static_cast<int>(v[1] >> 8) - static_cast<int>(clamp_u8(diff_h + (last[1] >> 8)));
        enc.encode_symbol(c.diff[3], static_cast<uint32_t>(corr) & 0xFF);
      }
      if (sym & 32) {
        diff_h = (diff_h + static_cast<int>(v[1] >> 8) - static_cast<int>(last[1] >> 8)) / 2;
        const int corr =
            static_cast<int>(v[2] >> 8) - static_cast<int>(clamp_u8(diff_h + (last[2] >> 8)));
        enc.encode_symbol(c.diff[5], static_cast<uint32_t>(corr) & 0xFF);
      }
    }
    if (nir_) {
      const uint32_t nsym =
          ((last[3] & 0xFF) != (v[3] & 0xFF)) | ((last[3] & 0xFF00) != (v[3] & 0xFF00)) << 1;
      nir_out_.enc.encode_symbol(c.nir_used, nsym);
      nir_out_.changed |= nsym != 0;
      if (nsym & 1) nir_out_.enc.encode_symbol(c.nir_diff[0], (v[3] - last[3]) & 0xFF);
      if (nsym & 2)
        nir_out_.enc.encode_symbol(c.nir_diff[1], ((v[3] >> 8) - (last[3] >> 8)) & 0xFF);
    }
    for (int i = 0; i < (nir_ ? 4 : 3); ++i) last[i] = static_cast<uint16_t>(v[i]);
  }

  Layer* layer(int i) { return i == 0 ? &rgb_out_ : &nir_out_; }

 private:
  struct Context {
    Context(const unsigned char* item, int values) {
      for (int i = 0; i < values; ++i) last[i] = get16(item + 2 * i);
    }
    explicit Context(const uint16_t* from) { std::memcpy(last, from, sizeof last); }
    uint16_t last[4] = {};
    SymbolModel byte_used{128};
    std::array<SymbolModel, 6> diff{SymbolModel(256), SymbolModel(256), SymbolModel(256),
                                    SymbolModel(256), SymbolModel(256), SymbolModel(256)};
    SymbolModel nir_used{4};
    std::array<SymbolModel, 2> nir_diff{SymbolModel(256), SymbolModel(256)};
  };
  // LASzip's version 3 context switch: a new channel starts from a copy of the current one's
  // last values; a channel seen before is compared, this once, with the current one's.
  uint16_t* switch_context(unsigned context) {
    uint16_t* last = ctx_[current_]->last;
    if (context != current_) {
      current_ = context;
      if (!ctx_[context]) {
        ctx_[context] = std::make_unique<Context>(last);
        last = ctx_[context]->last;
      }
    }
    return last;
  }

  bool nir_;
  unsigned current_ = 0;
  std::array<std::unique_ptr<Context>, 4> ctx_;
  InLayer rgb_, nir_in_;
  Layer rgb_out_, nir_out_;
};

// BYTE14 version 3: one layer per extra byte, each byte against the same byte of the last record
// (with RGB14's context switch).
class Byte14 {
 public:
  explicit Byte14(std::size_t n) : n_(n), in_(n), out_(n) {}
  std::size_t size() const { return n_; }
  int layers() const { return static_cast<int>(n_); }

  void init(const unsigned char* item, unsigned context) {
    current_ = context;
    ctx_[context] = std::make_unique<Context>(item, n_);
  }
  void open(const unsigned char* p, const uint32_t* sizes) {
    for (std::size_t i = 0; i < n_; ++i) {
      in_[i].open(p, sizes[i]);
      p += sizes[i];
    }
  }
  void decode(unsigned char* item, unsigned context) {
    unsigned char* last = switch_context(context);
    Context& c = *ctx_[current_];
    for (std::size_t i = 0; i < n_; ++i) {
      if (in_[i])
        last[i] = static_cast<unsigned char>(last[i] + in_[i].dec->decode_symbol(c.model(i)));
      item[i] = last[i];
    }
  }
  void encode(const unsigned char* item, unsigned context) {
    unsigned char* last = switch_context(context);
    Context& c = *ctx_[current_];
    for (std::size_t i = 0; i < n_; ++i) {
      const unsigned diff = static_cast<unsigned char>(item[i] - last[i]);
      out_[i].enc.encode_symbol(c.model(i), diff);
      out_[i].changed |= diff != 0;
      last[i] = item[i];
    }
  }
  Layer* layer(int i) { return &out_[static_cast<std::size_t>(i)]; }

 private:
  struct Context {
    Context(const unsigned char* item, std::size_t n) : last(item, item + n), models(n) {}
    // Created on first use: the decoder needs none for an empty layer (a constant byte).
    SymbolModel& model(std::size_t i) {
      if (!models[i]) models[i] = std::make_unique<SymbolModel>(256);
      return *models[i];
    }
    std::vector<unsigned char> last;
    std::vector<std::unique_ptr<SymbolModel>> models;
  };
  unsigned char* switch_context(unsigned context) {
    unsigned char* last = ctx_[current_]->last.data();
    if (context != current_) {
      current_ = context;
      if (!ctx_[context]) {
        ctx_[context] = std::make_unique<Context>(last, n_);
        last = ctx_[context]->last.data();
      }
    }
    return last;
  }

  std::size_t n_;
  unsigned current_ = 0;
  std::array<std::unique_ptr<Context>, 4> ctx_;
  std::vector<InLayer> in_;
  std::deque<Layer> out_;
};

// The item coders of one layered chunk: POINT14, then RGB14 or RGBNIR14, then BYTE14.
struct LayeredCoders {
  Point14 point;
  std::unique_ptr<Rgb14> rgb;
  std::unique_ptr<Byte14> bytes;
  std::size_t record_length = kPoint14Size;
  int layers = Point14::kLayers;

  explicit LayeredCoders(const std::vector<Item>& items) {
    for (const Item& it : items) {
      if (it.type == kItemRgb14 || it.type == kItemRgbNir14) {
        rgb = std::make_unique<Rgb14>(it.type == kItemRgbNir14);
        record_length += rgb->size();
        layers += rgb->layers();
      } else if (it.type == kItemByte14) {
        bytes = std::make_unique<Byte14>(it.size);
        record_length += it.size;
        layers += bytes->layers();
      }
    }
  }
  void init(const unsigned char* r) {
    const unsigned context = point.init(r);
    r += kPoint14Size;
    if (rgb) rgb->init(r, context), r += rgb->size();
    if (bytes) bytes->init(r, context);
  }
  void open(const unsigned char* p, const uint32_t* sizes) {
    point.open(p, sizes);
    for (int i = 0; i < Point14::kLayers; ++i) p += sizes[i];
    sizes += Point14::kLayers;
    if (rgb) {
      rgb->open(p, sizes);
      for (int i = 0; i < rgb->layers(); ++i) p += sizes[i];
      sizes += rgb->layers();
    }
    if (bytes) bytes->open(p, sizes);
  }
  // Records 1..count-1 at out + i * rl. The layers are separate streams: each is decoded over
  // the whole chunk in turn (the points first, which give the others their contexts), so that
  // one decoder's models and branches stay hot.
  void decode_all(unsigned char* out, uint64_t count, std::size_t rl) {
    std::vector<uint8_t> contexts(count);
    point.decode_layers(out, count, rl, contexts.data());
    std::size_t at = kPoint14Size;
    if (rgb) {
      for (uint64_t i = 1; i < count; ++i) rgb->decode(out + i * rl + at, contexts[i]);
      at += rgb->size();
    }
    if (bytes)
      for (uint64_t i = 1; i < count; ++i) bytes->decode(out + i * rl + at, contexts[i]);
  }
  void encode(const unsigned char* r) {
    const unsigned context = point.encode(r);
    r += kPoint14Size;
    if (rgb) rgb->encode(r, context), r += rgb->size();
    if (bytes) bytes->encode(r, context);
  }
  // The layers in file order.
  std::vector<Layer*> all_layers() {
    std::vector<Layer*> v;
    for (int i = 0; i < Point14::kLayers; ++i) v.push_back(point.layers() + i);
    if (rgb)
      for (int i = 0; i < rgb->layers(); ++i) v.push_back(rgb->layer(i));
    if (bytes)
      for (int i = 0; i < bytes->layers(); ++i) v.push_back(bytes->layer(i));
    return v;
  }
};

}  // namespace

std::size_t decode_layered_chunk(std::span<const unsigned char> bytes,
                                 const std::vector<Item>& items, uint64_t count,
                                 unsigned char* out) {
  LayeredCoders coders(items);
  const std::size_t rl = coders.record_length;
  const std::size_t head = rl + 4 + 4 * static_cast<std::size_t>(coders.layers);
  if (bytes.size() < head)
    throw LazDataError("chunk of " + std::to_string(bytes.size()) +
                       " bytes is shorter than its first point, point count and " +
                       std::to_string(coders.layers) + " layer sizes (" + std::to_string(head) +
                       " bytes)");
  std::memcpy(out, bytes.data(), rl);
  const uint32_t stored = get32(bytes.data() + rl);
  if (stored != count)
    throw LazDataError("chunk says it holds " + std::to_string(stored) +
                       " points, the chunk table " + std::to_string(count));
  std::vector<uint32_t> sizes(static_cast<std::size_t>(coders.layers));
  uint64_t total = 0;
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    sizes[i] = get32(bytes.data() + rl + 4 + 4 * i);
    total += sizes[i];
  }
  if (total > bytes.size() - head)
    throw LazDataError("its layers claim " + std::to_string(total) + " bytes, " +
                       std::to_string(bytes.size() - head) + " follow their sizes");
  coders.init(out);
  if (count > 1) {
    coders.open(bytes.data() + head, sizes.data());
    coders.decode_all(out, count, rl);
  }
  return head + static_cast<std::size_t>(total);
}

void encode_layered_chunk(const unsigned char* records, uint64_t count,
                          const std::vector<Item>& items, std::vector<unsigned char>& out) {
  LayeredCoders coders(items);
  const std::size_t rl = coders.record_length;
  out.insert(out.end(), records, records + rl);
  coders.init(records);
  for (uint64_t i = 1; i < count; ++i) coders.encode(records + i * rl);
  const std::vector<Layer*> layers = coders.all_layers();
  unsigned char word[4];
  put32(word, static_cast<uint32_t>(count));
  out.insert(out.end(), word, word + 4);
  // X/Y and Z always; another layer only when its field changed within the chunk.
  for (std::size_t i = 0; i < layers.size(); ++i) {
    Layer& l = *layers[i];
    const bool keep = i < 2 || l.changed;
    if (keep) l.enc.done();
    put32(word, keep ? static_cast<uint32_t>(l.bytes.size()) : 0);
    out.insert(out.end(), word, word + 4);
  }
  for (std::size_t i = 0; i < layers.size(); ++i)
    if (i < 2 || layers[i]->changed)
      out.insert(out.end(), layers[i]->bytes.begin(), layers[i]->bytes.end());
}

}  // namespace splatkit::laz
