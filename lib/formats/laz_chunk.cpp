#include "formats/laz_chunk.h"

#include <array>
#include <cstring>
#include <memory>

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

// Contexts by return number r and number of returns n (LASzip's completed tables: files that
// count returns from 0 or mix r and n up still get distinct contexts).
constexpr uint8_t kReturnMap[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},
    {13, 1, 2, 4, 7, 11, 11, 10},    {12, 3, 4, 5, 8, 12, 12, 11},
    {11, 6, 7, 8, 9, 13, 13, 12},    {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15}};
constexpr uint8_t kReturnLevel[8][8] = {{0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6},
                                        {2, 1, 0, 1, 2, 3, 4, 5}, {3, 2, 1, 0, 1, 2, 3, 4},
                                        {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2},
                                        {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0}};

// POINT10 version 2: x, y, z, intensity, flags, classification, scan angle, user data, source.
class Point10 {
 public:
  static constexpr std::size_t kSize = 20;

  void init(const unsigned char* item) {
    std::memcpy(last_, item, kSize);
    last_[12] = last_[13] = 0;
  }

  SPLATKIT_LAZ_INLINE void decode(ArithmeticDecoder& dec, unsigned char* item) {
    const uint32_t changed = dec.decode_symbol(changed_values_);
    unsigned r, n, m, l;
    if (changed) {
      if (changed & 32)
        last_[14] = static_cast<unsigned char>(dec.decode_symbol(bit_byte_[last_[14]]));
      r = last_[14] & 7;
      n = (last_[14] >> 3) & 7;
      m = kReturnMap[n][r];
      l = kReturnLevel[n][r];
      if (changed & 16) {
        last_intensity_[m] =
            static_cast<uint16_t>(ic_intensity_.decompress(dec, last_intensity_[m], m < 3 ? m : 3));
      }
      put16(last_ + 12, last_intensity_[m]);
      if (changed & 8)
        last_[15] = static_cast<unsigned char>(dec.decode_symbol(classification_[last_[15]]));
      if (changed & 4) {
        const uint32_t v = dec.decode_symbol(scan_angle_[(last_[14] >> 6) & 1]);
        last_[16] = static_cast<unsigned char>(v + last_[16]);
      }
      if (changed & 2)
        last_[17] = static_cast<unsigned char>(dec.decode_symbol(user_data_[last_[17]]));
      if (changed & 1)
        put16(last_ + 18, static_cast<uint32_t>(ic_source_.decompress(dec, get16(last_ + 18), 0)));
    } else {
      r = last_[14] & 7;
      n = (last_[14] >> 3) & 7;
      m = kReturnMap[n][r];
      l = kReturnLevel[n][r];
    }
    int32_t diff = ic_dx_.decompress(dec, median_x_[m].get(), n == 1);
    put32(last_, static_cast<uint32_t>(wrap_add(static_cast<int32_t>(get32(last_)), diff)));
    median_x_[m].add(diff);
    uint32_t k_bits = ic_dx_.k();
    diff = ic_dy_.decompress(dec, median_y_[m].get(), (n == 1) + (k_bits < 20 ? k_bits & ~1u : 20));
    put32(last_ + 4, static_cast<uint32_t>(wrap_add(static_cast<int32_t>(get32(last_ + 4)), diff)));
    median_y_[m].add(diff);
    k_bits = (ic_dx_.k() + ic_dy_.k()) / 2;
    last_height_[l] =
        ic_z_.decompress(dec, last_height_[l], (n == 1) + (k_bits < 18 ? k_bits & ~1u : 18));
    put32(last_ + 8, static_cast<uint32_t>(last_height_[l]));
    std::memcpy(item, last_, kSize);
  }

  void encode(ArithmeticEncoder& enc, const unsigned char* item) {
    const unsigned r = item[14] & 7, n = (item[14] >> 3) & 7;
    const unsigned m = kReturnMap[n][r], l = kReturnLevel[n][r];
    const uint16_t intensity = get16(item + 12);
    const uint32_t changed = (last_[14] != item[14]) << 5 | (last_intensity_[m] != intensity) << 4 |
                             (last_[15] != item[15]) << 3 | (last_[16] != item[16]) << 2 |
                             (last_[17] != item[17]) << 1 | (get16(last_ + 18) != get16(item + 18));
    enc.encode_symbol(changed_values_, changed);
    if (changed & 32) enc.encode_symbol(bit_byte_[last_[14]], item[14]);
    if (changed & 16) {
      ic_intensity_.compress(enc, last_intensity_[m], intensity, m < 3 ? m : 3);
      last_intensity_[m] = intensity;
    }
    if (changed & 8) enc.encode_symbol(classification_[last_[15]], item[15]);
    if (changed & 4)
      enc.encode_symbol(scan_angle_[(item[14] >> 6) & 1],
                        static_cast<unsigned char>(item[16] - last_[16]));
    if (changed & 2) enc.encode_symbol(user_data_[last_[17]], item[17]);
    if (changed & 1) ic_source_.compress(enc, get16(last_ + 18), get16(item + 18), 0);
    int32_t diff = wrap_sub(static_cast<int32_t>(get32(item)), static_cast<int32_t>(get32(last_)));
    ic_dx_.compress(enc, median_x_[m].get(), diff, n == 1);
    median_x_[m].add(diff);
    uint32_t k_bits = ic_dx_.k();
    diff = wrap_sub(static_cast<int32_t>(get32(item + 4)), static_cast<int32_t>(get32(last_ + 4)));
    ic_dy_.compress(enc, median_y_[m].get(), diff, (n == 1) + (k_bits < 20 ? k_bits & ~1u : 20));
    median_y_[m].add(diff);
    k_bits = (ic_dx_.k() + ic_dy_.k()) / 2;
    const int32_t z = static_cast<int32_t>(get32(item + 8));
    ic_z_.compress(enc, last_height_[l], z, (n == 1) + (k_bits < 18 ? k_bits & ~1u : 18));
    last_height_[l] = z;
    std::memcpy(last_, item, kSize);
  }

 private:
  unsigned char last_[kSize] = {};
  std::array<uint16_t, 16> last_intensity_{};
  std::array<int32_t, 8> last_height_{};
  std::array<Median5, 16> median_x_{}, median_y_{};
  SymbolModel changed_values_{64};
  IntegerCompressor ic_intensity_{16, 4};
  SymbolModel scan_angle_[2] = {SymbolModel(256), SymbolModel(256)};
  IntegerCompressor ic_source_{16, 1};
  LazyModels bit_byte_, classification_, user_data_;
  IntegerCompressor ic_dx_{32, 2}, ic_dy_{32, 22}, ic_z_{32, 20};
};

// GPSTIME11 version 2 (laz_gps_time.h), on the record's 8 bytes.
class GpsTime11 {
 public:
  static constexpr std::size_t kSize = 8;
  void init(const unsigned char* item) { model_.set_first(static_cast<int64_t>(get64(item))); }
  SPLATKIT_LAZ_INLINE void decode(ArithmeticDecoder& dec, unsigned char* item) {
    put64(item, static_cast<uint64_t>(model_.decode(dec)));
  }
  void encode(ArithmeticEncoder& enc, const unsigned char* item) {
    model_.encode(enc, static_cast<int64_t>(get64(item)));
  }

 private:
  GpsTimeModel<true> model_;
};

// RGB12 version 2: which bytes changed, then each changed byte against a prediction from the
// changes of the channels before it.
class Rgb12 {
 public:
  static constexpr std::size_t kSize = 6;

  void init(const unsigned char* item) {
    for (int c = 0; c < 3; ++c) last_[c] = get16(item + 2 * c);
  }

  SPLATKIT_LAZ_INLINE void decode(ArithmeticDecoder& dec, unsigned char* item) {
    uint32_t v[3];
    const uint32_t sym = dec.decode_symbol(byte_used_);
    v[0] =
        (sym & 1) ? ((dec.decode_symbol(diff_[0]) + (last_[0] & 0xFF)) & 0xFF) : (last_[0] & 0xFF);
    v[0] |= (sym & 2) ? ((dec.decode_symbol(diff_[1]) + (last_[0] >> 8)) & 0xFF) << 8
                      : (last_[0] & 0xFF00);
    if (sym & 64) {
      int diff = static_cast<int>(v[0] & 0xFF) - static_cast<int>(last_[0] & 0xFF);
      v[1] = (sym & 4) ? ((dec.decode_symbol(diff_[2]) + clamp_u8(diff + (last_[1] & 0xFF))) & 0xFF)
                       : (last_[1] & 0xFF);
      if (sym & 16) {
        diff = (diff + static_cast<int>(v[1] & 0xFF) - static_cast<int>(last_[1] & 0xFF)) / 2;
        v[2] = (dec.decode_symbol(diff_[4]) + clamp_u8(diff + (last_[2] & 0xFF))) & 0xFF;
      } else {
        v[2] = last_[2] & 0xFF;
      }
      diff = static_cast<int>(v[0] >> 8) - static_cast<int>(last_[0] >> 8);
      v[1] |= (sym & 8)
                  ? ((dec.decode_symbol(diff_[3]) + clamp_u8(diff + (last_[1] >> 8))) & 0xFF) << 8
                  : (last_[1] & 0xFF00);
      if (sym & 32) {
        diff = (diff + static_cast<int>(v[1] >> 8) - static_cast<int>(last_[1] >> 8)) / 2;
        v[2] |= ((dec.decode_symbol(diff_[5]) + clamp_u8(diff + (last_[2] >> 8))) & 0xFF) << 8;
      } else {
        v[2] |= last_[2] & 0xFF00;
      }
    } else {
      v[1] = v[2] = v[0];
    }
    for (int c = 0; c < 3; ++c) {
      last_[c] = static_cast<uint16_t>(v[c]);
      put16(item + 2 * c, v[c]);
    }
  }

  void encode(ArithmeticEncoder& enc, const unsigned char* item) {
    uint32_t v[3];
    for (int c = 0; c < 3; ++c) v[c] = get16(item + 2 * c);
    uint32_t sym =
        ((last_[0] & 0xFF) != (v[0] & 0xFF)) << 0 | ((last_[0] & 0xFF00) != (v[0] & 0xFF00)) << 1 |
        ((last_[1] & 0xFF) != (v[1] & 0xFF)) << 2 | ((last_[1] & 0xFF00) != (v[1] & 0xFF00)) << 3 |
        ((last_[2] & 0xFF) != (v[2] & 0xFF)) << 4 | ((last_[2] & 0xFF00) != (v[2] & 0xFF00)) << 5;
    sym |= (v[0] != v[1] || v[0] != v[2]) << 6;
    enc.encode_symbol(byte_used_, sym);
    int diff_l = 0, diff_h = 0;
    if (sym & 1) {
      diff_l = static_cast<int>(v[0] & 0xFF) - static_cast<int>(last_[0] & 0xFF);
      enc.encode_symbol(diff_[0], static_cast<uint32_t>(diff_l) & 0xFF);
    }
    if (sym & 2) {
      diff_h = static_cast<int>(v[0] >> 8) - static_cast<int>(last_[0] >> 8);
      enc.encode_symbol(diff_[1], static_cast<uint32_t>(diff_h) & 0xFF);
    }
    if (sym & 64) {
      if (sym & 4) {
        const int corr =
            static_cast<int>(v[1] & 0xFF) - static_cast<int>(clamp_u8(diff_l + (last_[1] & 0xFF)));
        enc.encode_symbol(diff_[2], static_cast<uint32_t>(corr) & 0xFF);
      }
      if (sym & 16) {
        diff_l = (diff_l + static_cast<int>(v[1] & 0xFF) - static_cast<int>(last_[1] & 0xFF)) / 2;
        const int corr =
            static_cast<int>(v[2] & 0xFF) - static_cast<int>(clamp_u8(diff_l + (last_[2] & 0xFF)));
        enc.encode_symbol(diff_[4], static_cast<uint32_t>(corr) & 0xFF);
      }
      if (sym & 8) {
        const int corr =
            static_cast<int>(v[1] >> 8) - static_cast<int>(clamp_u8(diff_h + (last_[1] >> 8)));
        enc.encode_symbol(diff_[3], static_cast<uint32_t>(corr) & 0xFF);
      }
      if (sym & 32) {
        diff_h = (diff_h + static_cast<int>(v[1] >> 8) - static_cast<int>(last_[1] >> 8)) / 2;
        const int corr =
            static_cast<int>(v[2] >> 8) - static_cast<int>(clamp_u8(diff_h + (last_[2] >> 8)));
        enc.encode_symbol(diff_[5], static_cast<uint32_t>(corr) & 0xFF);
      }
    }
    for (int c = 0; c < 3; ++c) last_[c] = static_cast<uint16_t>(v[c]);
  }

 private:
  uint16_t last_[3] = {};
  SymbolModel byte_used_{128};
  SymbolModel diff_[6] = {SymbolModel(256), SymbolModel(256), SymbolModel(256),
                          SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

// BYTE version 2: each extra byte against the same byte of the previous record.
class Bytes {
 public:
  explicit Bytes(std::size_t n) : last_(n) {
    models_.reserve(n);
    for (std::size_t i = 0; i < n; ++i) models_.emplace_back(256);
  }
  std::size_t size() const { return last_.size(); }
  void init(const unsigned char* item) { std::memcpy(last_.data(), item, last_.size()); }
  SPLATKIT_LAZ_INLINE void decode(ArithmeticDecoder& dec, unsigned char* item) {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      last_[i] = static_cast<unsigned char>(last_[i] + dec.decode_symbol(models_[i]));
      item[i] = last_[i];
    }
  }
  void encode(ArithmeticEncoder& enc, const unsigned char* item) {
    for (std::size_t i = 0; i < last_.size(); ++i) {
      enc.encode_symbol(models_[i], static_cast<unsigned char>(item[i] - last_[i]));
      last_[i] = item[i];
    }
  }

 private:
  std::vector<unsigned char> last_;
  std::vector<SymbolModel> models_;
};

// The item coders of one chunk, in record order.
struct ChunkCoders {
  std::unique_ptr<Point10> point;
  std::unique_ptr<GpsTime11> gps;
  std::unique_ptr<Rgb12> rgb;
  std::unique_ptr<Bytes> bytes;
  std::size_t record_length = 0;

  explicit ChunkCoders(const std::vector<Item>& items) {
    for (const Item& it : items) {
      if (it.type == kItemPoint10)
        point = std::make_unique<Point10>();
      else if (it.type == kItemGpsTime11)
        gps = std::make_unique<GpsTime11>();
      else if (it.type == kItemRgb12)
        rgb = std::make_unique<Rgb12>();
      else if (it.type == kItemByte)
        bytes = std::make_unique<Bytes>(it.size);
      record_length += it.size;
    }
  }
  // Offsets follow items_for_format's order: POINT10, GPSTIME11, RGB12, BYTE.
  void init(const unsigned char* r) {
    point->init(r);
    r += Point10::kSize;
    if (gps) gps->init(r), r += GpsTime11::kSize;
    if (rgb) rgb->init(r), r += Rgb12::kSize;
    if (bytes) bytes->init(r);
  }
  SPLATKIT_LAZ_INLINE void decode(ArithmeticDecoder& dec, unsigned char* r) {
    point->decode(dec, r);
    r += Point10::kSize;
    if (gps) gps->decode(dec, r), r += GpsTime11::kSize;
    if (rgb) rgb->decode(dec, r), r += Rgb12::kSize;
    if (bytes) bytes->decode(dec, r);
  }
  void encode(ArithmeticEncoder& enc, const unsigned char* r) {
    point->encode(enc, r);
    r += Point10::kSize;
    if (gps) gps->encode(enc, r), r += GpsTime11::kSize;
    if (rgb) rgb->encode(enc, r), r += Rgb12::kSize;
    if (bytes) bytes->encode(enc, r);
  }
};

}  // namespace

std::string item_name(uint16_t type) {
  static const char* names[] = {"BYTE",    "SHORT",   "INT",       "LONG",         "FLOAT",
                                "DOUBLE",  "POINT10", "GPSTIME11", "RGB12",        "WAVEPACKET13",
                                "POINT14", "RGB14",   "RGBNIR14",  "WAVEPACKET14", "BYTE14"};
  return type < std::size(names) ? names[type] : "type " + std::to_string(type);
}

bool parse_laszip_vlr(std::span<const unsigned char> p, LaszipVlr& vlr, std::string& error) {
  if (p.size() < 34) {
    error = "LASzip VLR is " + std::to_string(p.size()) + " bytes, shorter than its 34-byte header";
    return false;
  }
  vlr.compressor = get16(&p[0]);
  vlr.coder = get16(&p[2]);
  vlr.version_major = p[4];
  vlr.version_minor = p[5];
  vlr.revision = get16(&p[6]);
  vlr.options = get32(&p[8]);
  vlr.chunk_size = get32(&p[12]);
  vlr.special_evlr_count = static_cast<int64_t>(get64(&p[16]));
  vlr.special_evlr_offset = static_cast<int64_t>(get64(&p[24]));
  const uint16_t n = get16(&p[32]);
  if (p.size() != 34 + 6 * std::size_t{n}) {
    error = "LASzip VLR lists " + std::to_string(n) + " items (" + std::to_string(34 + 6 * n) +
            " bytes) but is " + std::to_string(p.size()) + " bytes long";
    return false;
  }
  vlr.items.clear();
  for (uint16_t i = 0; i < n; ++i)
    vlr.items.push_back({get16(&p[34 + 6 * i]), get16(&p[36 + 6 * i]), get16(&p[38 + 6 * i])});
  return true;
}

std::vector<unsigned char> laszip_vlr_payload(const LaszipVlr& vlr) {
  std::vector<unsigned char> p(34 + 6 * vlr.items.size());
  put16(&p[0], vlr.compressor);
  put16(&p[2], vlr.coder);
  p[4] = vlr.version_major;
  p[5] = vlr.version_minor;
  put16(&p[6], vlr.revision);
  put32(&p[8], vlr.options);
  put32(&p[12], vlr.chunk_size);
  put64(&p[16], static_cast<uint64_t>(vlr.special_evlr_count));
  put64(&p[24], static_cast<uint64_t>(vlr.special_evlr_offset));
  put16(&p[32], static_cast<uint32_t>(vlr.items.size()));
  for (std::size_t i = 0; i < vlr.items.size(); ++i) {
    put16(&p[34 + 6 * i], vlr.items[i].type);
    put16(&p[36 + 6 * i], vlr.items[i].size);
    put16(&p[38 + 6 * i], vlr.items[i].version);
  }
  return p;
}

std::vector<Item> items_for_format(int format, uint16_t record_length) {
  if (format >= 6) {
    static constexpr uint16_t kBase14[3] = {30, 36, 38};
    std::vector<Item> items{{kItemPoint14, 30, 3}};
    if (format == 7) items.push_back({kItemRgb14, 6, 3});
    if (format == 8) items.push_back({kItemRgbNir14, 8, 3});
    if (record_length > kBase14[format - 6])
      items.push_back({kItemByte14, static_cast<uint16_t>(record_length - kBase14[format - 6]), 3});
    return items;
  }
  static constexpr uint16_t kBase[4] = {20, 28, 26, 34};
  std::vector<Item> items{{kItemPoint10, 20, 2}};
  if (format == 1 || format == 3) items.push_back({kItemGpsTime11, 8, 2});
  if (format == 2 || format == 3) items.push_back({kItemRgb12, 6, 2});
  if (record_length > kBase[format])
    items.push_back({kItemByte, static_cast<uint16_t>(record_length - kBase[format]), 2});
  return items;
}

std::size_t decode_chunk(std::span<const unsigned char> bytes, const std::vector<Item>& items,
                         uint64_t count, unsigned char* out) {
  if (!items.empty() && items[0].type == kItemPoint14)
    return decode_layered_chunk(bytes, items, count, out);
  ChunkCoders coders(items);
  const std::size_t rl = coders.record_length;
  if (bytes.size() < rl) throw LazDataError("chunk is shorter than its first (raw) point");
  std::memcpy(out, bytes.data(), rl);
  coders.init(out);
  ArithmeticDecoder dec(bytes.data() + rl, bytes.data() + bytes.size());
  dec.init();
  for (uint64_t i = 1; i < count; ++i) coders.decode(dec, out + i * rl);
  return static_cast<std::size_t>(dec.position() - bytes.data());
}

void encode_chunk(const unsigned char* records, uint64_t count, const std::vector<Item>& items,
                  std::vector<unsigned char>& out) {
  if (!items.empty() && items[0].type == kItemPoint14) {
    encode_layered_chunk(records, count, items, out);
    return;
  }
  ChunkCoders coders(items);
  const std::size_t rl = coders.record_length;
  out.insert(out.end(), records, records + rl);
  coders.init(records);
  ArithmeticEncoder enc(out);
  for (uint64_t i = 1; i < count; ++i) coders.encode(enc, records + i * rl);
  enc.done();
}

std::vector<ChunkEntry> decode_chunk_table(std::span<const unsigned char> bytes, uint32_t chunks,
                                           bool variable, std::size_t* used) {
  std::vector<ChunkEntry> table;
  if (used) *used = 0;
  if (chunks == 0) return table;
  ArithmeticDecoder dec(bytes.data(), bytes.data() + bytes.size());
  dec.init();
  IntegerCompressor ic(32, 2);
  int32_t last_points = 0, last_bytes = 0;
  for (uint32_t i = 0; i < chunks; ++i) {
    ChunkEntry e;
    if (variable) {
      last_points = ic.decompress(dec, last_points, 0);
      e.points = static_cast<uint32_t>(last_points);
    }
    last_bytes = ic.decompress(dec, last_bytes, 1);
    e.bytes = static_cast<uint32_t>(last_bytes);
    table.push_back(e);
  }
  if (used) *used = static_cast<std::size_t>(dec.position() - bytes.data());
  return table;
}

void encode_chunk_table(const std::vector<ChunkEntry>& chunks, bool variable,
                        std::vector<unsigned char>& out) {
  unsigned char head[8];
  put32(head, 0);
  put32(head + 4, static_cast<uint32_t>(chunks.size()));
  out.insert(out.end(), head, head + 8);
  if (chunks.empty()) return;
  ArithmeticEncoder enc(out);
  IntegerCompressor ic(32, 2);
  int32_t last_points = 0, last_bytes = 0;
  for (const ChunkEntry& e : chunks) {
    if (variable) {
      ic.compress(enc, last_points, static_cast<int32_t>(e.points), 0);
      last_points = static_cast<int32_t>(e.points);
    }
    ic.compress(enc, last_bytes, static_cast<int32_t>(e.bytes), 1);
    last_bytes = static_cast<int32_t>(e.bytes);
  }
  enc.done();
}

}  // namespace splatkit::laz
