#include "formats/splk.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "splatkit/crc32c.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit {
namespace {

// Bulk columns are read, checksummed and converted in steps of this size: the step is still in
// cache when its CRC is computed, and on a pipe a vector never grows by more than one step
// beyond what was read (plus the vector's own geometric growth).
constexpr std::size_t kStep = std::size_t{4} << 20;

constexpr unsigned char kMagic[8] = {0x89, 'S', 'P', 'L', 'K', '\r', '\n', 0x1A};
constexpr uint16_t kMajor = 1;
constexpr uint32_t kKnownFileFlags = 0;
constexpr uint32_t kKnownChunkFlags = kSplkChunkCritical | kSplkChunkTiedToSplats;
constexpr std::size_t kHeaderBytes = 16;
constexpr std::size_t kChunkHeaderBytes = 20;
constexpr std::size_t kSpltFixedBytes = 64;
constexpr uint32_t kSpltHasViewpoint = 1;
constexpr uint8_t kCoreColumn = 0;
constexpr uint8_t kExtraColumn = 1;
// Chunks a reader accepts in one file (END included): the bookkeeping of a chunk (its header
// entry, a carried copy) costs far more than its 20 header bytes, so a file of millions of empty
// chunks would take gigabytes. splatkit writes a handful.
constexpr std::size_t kMaxChunks = 65536;

using ChunkType = std::array<char, 4>;
constexpr ChunkType kMeta{'M', 'E', 'T', 'A'};
constexpr ChunkType kSplt{'S', 'P', 'L', 'T'};
constexpr ChunkType kFace{'F', 'A', 'C', 'E'};
constexpr ChunkType kElps{'E', 'L', 'P', 'S'};  // elliptic splats, since 1.2
constexpr ChunkType kEnd{'E', 'N', 'D', ' '};
// Chunk types registered in minor version 1 (splk.h).
constexpr std::array<const char*, 4> kSince1_1{kSplkGraphType, kSplkClassType, kSplkClipType,
                                               kSplkSurfaceType};

// Registered types that a later stage decodes from LoadedCloud::chunks: read_splk carries them
// through even when they are critical. None so far; a new type goes here (formats/splk.md,
// "Adding a chunk type").
constexpr std::array<ChunkType, 0> kCarriedTypes{};

static_assert(sizeof(Vec3f) == 12, "Vec3f columns are read and written as 3 packed float32");
static_assert(sizeof(std::array<uint16_t, 3>) == 6, "16-bit colours are 3 packed uint16");
constexpr bool kLittleEndianHost = std::endian::native == std::endian::little;

// --- little-endian encoding ---

template <class U>
void put_le(std::string& s, U v) {
  for (std::size_t i = 0; i < sizeof(U); ++i) s.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void put_f64(std::string& s, double v) { put_le(s, std::bit_cast<uint64_t>(v)); }

template <class U>
U get_le(const unsigned char* p) {
  U v = 0;
  for (std::size_t i = 0; i < sizeof(U); ++i) v |= static_cast<U>(static_cast<U>(p[i]) << (8 * i));
  return v;
}
double get_f64(const unsigned char* p) { return std::bit_cast<double>(get_le<uint64_t>(p)); }

// Reverses each `width`-byte value in place (big-endian hosts only).
[[maybe_unused]] void swap_values(void* data, std::size_t bytes, std::size_t width) {
  auto* p = static_cast<unsigned char*>(data);
  for (std::size_t i = 0; i + width <= bytes; i += width) std::reverse(p + i, p + i + width);
}

std::string type_name(const ChunkType& t) { return std::string(t.data(), 4); }

std::string hex32(uint32_t v) {
  char buf[9];
  std::snprintf(buf, sizeof buf, "%08x", v);
  return buf;
}

// Unicode Table 3-7 (well-formed UTF-8): what nlohmann-json accepts when it dumps a string.
bool is_utf8(std::string_view s) {
  const auto* p = reinterpret_cast<const unsigned char*>(s.data());
  std::size_t i = 0, n = s.size();
  while (i < n) {
    unsigned char c = p[i];
    std::size_t len = c < 0x80                   ? 1
                      : (c >= 0xC2 && c <= 0xDF) ? 2
                      : (c >= 0xE0 && c <= 0xEF) ? 3
                      : (c >= 0xF0 && c <= 0xF4) ? 4
                                                 : 0;
    if (len == 0 || i + len > n) return false;
    unsigned char lo = 0x80, hi = 0xBF;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
    for (std::size_t k = 1; k < len; ++k) {
      unsigned char b = p[i + k];
      if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xBF)) return false;
    }
    i += len;
  }
  return true;
}

// A-Z a-z 0-9, spaces only at the end, not all spaces.
bool is_valid_type(const ChunkType& t) {
  bool padding = false;
  for (std::size_t i = 0; i < 4; ++i) {
    unsigned char c = static_cast<unsigned char>(t[i]);
    bool alnum = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
    if (c == ' ' && i > 0)
      padding = true;
    else if (!alnum || padding)
      return false;
  }
  return true;
}

// --- extra attributes ---

template <class T>
T load_value(const unsigned char* p) {
  using U = std::conditional_t<
      sizeof(T) == 1, uint8_t,
      std::conditional_t<sizeof(T) == 2, uint16_t,
                         std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  return std::bit_cast<T>(get_le<U>(p));
}

template <class T>
void store_value(unsigned char* p, T v) {
  using U = std::conditional_t<
      sizeof(T) == 1, uint8_t,
      std::conditional_t<sizeof(T) == 2, uint16_t,
                         std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
  U u = std::bit_cast<U>(v);
  for (std::size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<unsigned char>(u >> (8 * i));
}

// Calls f(T{}) with the C++ type of a scalar type code.
template <class F>
void with_scalar_type(ScalarType t, F&& f) {
  switch (t) {
    case ScalarType::kInt8:
      f(int8_t{});
      break;
    case ScalarType::kUInt8:
      f(uint8_t{});
      break;
    case ScalarType::kInt16:
      f(int16_t{});
      break;
    case ScalarType::kUInt16:
      f(uint16_t{});
      break;
    case ScalarType::kInt32:
      f(int32_t{});
      break;
    case ScalarType::kUInt32:
      f(uint32_t{});
      break;
    case ScalarType::kInt64:
      f(int64_t{});
      break;
    case ScalarType::kUInt64:
      f(uint64_t{});
      break;
    case ScalarType::kFloat32:
      f(float{});
      break;
    case ScalarType::kFloat64:
      f(double{});
      break;
  }
}

bool is_scalar_code(uint8_t code) {
  return code >= static_cast<uint8_t>(ScalarType::kInt8) &&
         code <= static_cast<uint8_t>(ScalarType::kFloat64);
}

// --- writing ---

// Where a payload goes: the first pass only measures and checksums it (the chunk header, which
// precedes the payload, holds both and the output may be a pipe), the second pass writes it.
class PayloadSink {
 public:
  explicit PayloadSink(OutputFile* out) : out_(out) {}
  void put(const void* data, std::size_t n) {
    if (n == 0) return;
    if (out_) {
      out_->write(data, n);
    } else {
      crc_ = crc32c(crc_, data, n);
      size_ += n;
    }
  }
  void put(const std::string& s) { put(s.data(), s.size()); }
  uint64_t size() const { return size_; }
  uint32_t crc() const { return crc_; }

 private:
  OutputFile* out_;
  uint64_t size_ = 0;
  uint32_t crc_ = 0;
};

// Puts `bytes` of packed `width`-byte values, byte-swapped on a big-endian host.
void put_packed(PayloadSink& sink, const void* data, std::size_t bytes, std::size_t width) {
  if constexpr (kLittleEndianHost) {
    sink.put(data, bytes);
  } else {
    std::vector<unsigned char> block;
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t off = 0; off < bytes; off += kStep) {
      std::size_t k = std::min(kStep, bytes - off);
      block.assign(p + off, p + off + k);
      swap_values(block.data(), k, width);
      sink.put(block.data(), k);
    }
  }
}

void put_column_header(PayloadSink& sink, const std::string& name, uint8_t kind, ScalarType type,
                       uint8_t components) {
  std::string h;
  put_le(h, static_cast<uint16_t>(name.size()));
  h += name;
  put_le(h, kind);
  put_le(h, static_cast<uint8_t>(type));
  put_le(h, components);
  sink.put(h);
}

void put_colors(PayloadSink& sink, const SplatCloud& c) {
  if (c.color_bits == 16) {
    put_packed(sink, c.colors.data(), c.colors.size() * 6, 2);
    return;
  }
  std::vector<unsigned char> block;
  for (std::size_t i = 0; i < c.colors.size(); i += kStep / 3) {
    std::size_t k = std::min(kStep / 3, c.colors.size() - i);
    block.resize(k * 3);
    for (std::size_t j = 0; j < k; ++j)
      for (std::size_t ch = 0; ch < 3; ++ch)
        block[j * 3 + ch] = static_cast<unsigned char>(c.colors[i + j][ch]);
    sink.put(block.data(), block.size());
  }
}

void put_extra(PayloadSink& sink, const ExtraAttribute& e) {
  put_column_header(sink, e.name, kExtraColumn, e.type(), 1);
  with_scalar_type(e.type(), [&](auto zero) {
    using T = decltype(zero);
    std::vector<unsigned char> block;
    const std::size_t per_block = kStep / sizeof(T);
    const std::span<const T> values = e.values.as<T>();
    for (std::size_t i = 0; i < values.size(); i += per_block) {
      std::size_t k = std::min(per_block, values.size() - i);
      block.resize(k * sizeof(T));
      for (std::size_t j = 0; j < k; ++j)
        store_value<T>(block.data() + j * sizeof(T), values[i + j]);
      sink.put(block.data(), block.size());
    }
  });
}

void put_splt(PayloadSink& sink, const SplatCloud& c) {
  const uint32_t columns = 1 + (c.has_normals() ? 1 : 0) + (c.has_radii() ? 1 : 0) +
                           (c.has_colors() ? 1 : 0) + static_cast<uint32_t>(c.extras.size());
  std::string h;
  put_le(h, static_cast<uint64_t>(c.size()));
  for (double o : c.origin) put_f64(h, o);
  put_le(h, c.viewpoint ? kSpltHasViewpoint : uint32_t{0});
  for (std::size_t i = 0; i < 3; ++i) put_f64(h, c.viewpoint ? (*c.viewpoint)[i] : 0.0);
  put_le(h, columns);
  sink.put(h);

  put_column_header(sink, "position", kCoreColumn, ScalarType::kFloat32, 3);
  put_packed(sink, c.positions.data(), c.size() * 12, 4);
  if (c.has_normals()) {
    put_column_header(sink, "normal", kCoreColumn, ScalarType::kFloat32, 3);
    put_packed(sink, c.normals.data(), c.size() * 12, 4);
  }
  if (c.has_radii()) {
    put_column_header(sink, "radius", kCoreColumn, ScalarType::kFloat32, 1);
    put_packed(sink, c.radii.data(), c.size() * 4, 4);
  }
  if (c.has_colors()) {
    put_column_header(sink, "color", kCoreColumn,
                      c.color_bits == 16 ? ScalarType::kUInt16 : ScalarType::kUInt8, 3);
    put_colors(sink, c);
  }
  for (const auto& e : c.extras) put_extra(sink, e);
}

void put_elps(PayloadSink& sink, const SplatCloud& c) {
  std::string h;
  put_le(h, static_cast<uint64_t>(c.size()));
  sink.put(h);
  put_packed(sink, c.axes.data(), c.size() * 12, 4);
  put_packed(sink, c.minor_radii.data(), c.size() * 4, 4);
}

void put_face(PayloadSink& sink, const SplatCloud& c) {
  std::string h;
  put_le(h, static_cast<uint64_t>(c.face_count()));
  put_le(h, static_cast<uint64_t>(c.face_indices.size()));
  sink.put(h);
  put_packed(sink, c.face_offsets.data(), c.face_offsets.size() * 4, 4);
  put_packed(sink, c.face_indices.data(), c.face_indices.size() * 4, 4);
}

template <class Body>
void write_chunk(OutputFile& out, const ChunkType& type, uint32_t flags, Body&& body) {
  PayloadSink measure(nullptr);
  body(measure);
  std::string h(type.data(), 4);
  put_le(h, flags);
  put_le(h, measure.size());
  put_le(h, measure.crc());
  out.write(h);
  PayloadSink sink(&out);
  body(sink);
}

// What the format cannot hold is refused before the first byte is written.
void check_writable(const LoadedCloud& doc, const OutputFile& out) {
  const SplatCloud& c = doc.cloud;
  c.check_consistent();
  for (std::size_t i = 0; i < c.size(); ++i) {
    const Vec3f& p = c.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw_output(out.path(), "point " + std::to_string(i) +
                                   " has a non-finite position; .splk does not store those");
  }
  std::set<std::string> names;
  for (const auto& e : c.extras) {
    if (e.name.empty() || e.name.size() > 0xFFFF || !is_utf8(e.name))
      throw_output(out.path(), "extra attribute name '" + e.name +
                                   "' is empty, longer than 65535 bytes or not UTF-8");
    if (!names.insert(e.name).second)
      throw_output(out.path(), "two extra attributes are named '" + e.name + "'");
  }
  if (!doc.metadata.is_null() && !doc.metadata.is_object())
    throw_output(out.path(), "metadata must be a JSON object");
  for (const RawChunk& r : doc.chunks) {
    ChunkType t{r.type[0], r.type[1], r.type[2], r.type[3]};
    if (!is_valid_type(t) || t == kMeta || t == kSplt || t == kFace || t == kElps || t == kEnd)
      throw_output(out.path(), "cannot carry a chunk of type '" + type_name(t) +
                                   "' (invalid or written by write_splk itself)");
    if (r.flags & ~kKnownChunkFlags)
      throw_output(out.path(), "chunk '" + type_name(t) + "' has unknown flag bits");
  }
}

// --- reading ---

struct ChunkHeader {
  ChunkType type{};
  uint32_t flags = 0;
  uint64_t size = 0;
  uint32_t crc = 0;
  uint64_t offset = 0;  // of the chunk header in the file
};

// One chunk's payload: reads stay inside it, and every failure names the chunk and where it
// starts. Its checksum follows from the stream's running one (the stream checksums every byte it
// hands out, and within a chunk only the payload reads it) before and after the payload.
class Payload {
 public:
  Payload(InputStream& in, const ChunkHeader& h)
      : in_(in), h_(h), left_(h.size), stream_crc_before_(in.checksum()) {}

  uint64_t left() const { return left_; }
  bool size_known() const { return in_.size_hint().has_value(); }

  [[noreturn]] void fail(const std::string& what) const {
    throw_bad_input(in_.path(), "chunk '" + type_name(h_.type) + "' at byte " +
                                    std::to_string(h_.offset) + ": " + what);
  }

  void read(void* dst, std::size_t n, const std::string& what) {
    if (n > left_)
      fail(what + " needs " + std::to_string(n) + " bytes but only " + std::to_string(left_) +
           " are left in the payload");
    std::size_t got = in_.read_some(dst, n);
    if (got != n)
      fail("payload truncated: " + std::to_string(h_.size) +
           " bytes declared, the file ends after " + std::to_string(h_.size - left_ + got));
    left_ -= n;
  }

  template <std::size_t N>
  std::array<unsigned char, N> fixed(const std::string& what) {
    std::array<unsigned char, N> b{};
    read(b.data(), N, what);
    return b;
  }

  // Fails unless `count` values of `width` bytes fit in what is left of the payload.
  void check_fits(uint64_t count, std::size_t width, const std::string& what) const {
    if (count > left_ / width)
      fail(what + ": " + std::to_string(count) + " values of " + std::to_string(width) +
           " bytes do not fit in the " + std::to_string(left_) + " bytes left in the payload");
  }

  // Reads `count` packed little-endian values (each T made of `width`-byte scalars) into v. The
  // vector grows step by step with what was read, so a lying size on a pipe cannot make it
  // allocate more than the bytes that really arrive (plus one step).
  template <class Vector>
  void read_array(Vector& v, uint64_t count, std::size_t width, const std::string& what) {
    using T = typename Vector::value_type;
    check_fits(count, sizeof(T), what);
    v.clear();
    if (in_.size_hint()) {  // count is checked against the file: one read into mapped pages
      sized_in_parallel(v, static_cast<std::size_t>(count));
      read(v.data(), v.size() * sizeof(T), what);
      if constexpr (!kLittleEndianHost) swap_values(v.data(), v.size() * sizeof(T), width);
      return;
    }
    const std::size_t per_step = std::max<std::size_t>(1, kStep / sizeof(T));
    while (v.size() < count) {
      std::size_t old = v.size();
      v.resize(old + static_cast<std::size_t>(std::min<uint64_t>(per_step, count - old)));
      read(v.data() + old, (v.size() - old) * sizeof(T), what);
      if constexpr (!kLittleEndianHost)
        swap_values(v.data() + old, (v.size() - old) * sizeof(T), width);
    }
  }

  // Checks that the payload was used up exactly and that its checksum matches.
  void finish() {
    if (left_ != 0) fail(std::to_string(left_) + " unused bytes at the end of the payload");
    const uint32_t crc = crc32c_combine(stream_crc_before_, in_.checksum(), h_.size);
    if (crc != h_.crc)
      fail("checksum mismatch: CRC-32C of the payload is " + hex32(crc) + ", the header says " +
           hex32(h_.crc));
  }

 private:
  InputStream& in_;
  const ChunkHeader& h_;
  uint64_t left_;
  uint32_t stream_crc_before_;
};

void read_file_header(InputStream& in, LoadedCloud& doc) {
  unsigned char h[kHeaderBytes];
  std::size_t got = in.read_some(h, kHeaderBytes);
  if (got >= 5 && std::memcmp(h + 1, "SPLK", 4) == 0) {
    std::size_t n = std::min<std::size_t>(got, 8);
    if (h[0] == 0x09)
      throw_bad_input(in.path(),
                      "damaged .splk magic: the high bit of byte 0 was cleared "
                      "(7-bit transfer)");
    if (n >= 7 && h[5] == '\n')
      throw_bad_input(in.path(),
                      "damaged .splk magic: \\r\\n became \\n (text-mode transfer "
                      "converted the line endings)");
    if (n >= 7 && h[5] == '\r' && h[6] == '\r')
      throw_bad_input(in.path(),
                      "damaged .splk magic: \\n became \\r\\n (text-mode transfer "
                      "converted the line endings)");
  }
  if (got < 8 && std::memcmp(h, kMagic, got) == 0)
    throw_bad_input(in.path(), "truncated header: " + std::to_string(got) + " of 16 bytes");
  if (std::memcmp(h, kMagic, 8) != 0) throw_bad_input(in.path(), "not a .splk file (bad magic)");
  if (got < kHeaderBytes)
    throw_bad_input(in.path(), "truncated header: " + std::to_string(got) + " of 16 bytes");
  const uint16_t major = get_le<uint16_t>(h + 8), minor = get_le<uint16_t>(h + 10);
  const uint32_t flags = get_le<uint32_t>(h + 12);
  const std::string version = std::to_string(major) + "." + std::to_string(minor);
  if (major != kMajor)
    throw_unsupported(in.path(), ".splk version " + version +
                                     " is not supported (this reader "
                                     "reads 1.x; a newer splatkit may read it)");
  if (flags & ~kKnownFileFlags)
    throw_unsupported(in.path(), "file flags 0x" + hex32(flags) +
                                     " have bits this reader does not "
                                     "know (a newer splatkit may read it)");
  doc.header["version"] = version;
  doc.header["flags"] = flags;
  doc.header["chunks"] = nlohmann::json::array();
}

// False at a clean end of file (0 bytes where a chunk header would start).
bool read_chunk_header(InputStream& in, ChunkHeader& h) {
  unsigned char b[kChunkHeaderBytes];
  h.offset = in.offset();
  std::size_t got = in.read_some(b, kChunkHeaderBytes);
  if (got == 0) return false;
  if (got < kChunkHeaderBytes)
    throw_bad_input(in.path(), "byte " + std::to_string(h.offset) + ": truncated chunk header: " +
                                   std::to_string(got) + " of 20 bytes");
  std::memcpy(h.type.data(), b, 4);
  h.flags = get_le<uint32_t>(b + 4);
  h.size = get_le<uint64_t>(b + 8);
  h.crc = get_le<uint32_t>(b + 16);
  const std::string where = "byte " + std::to_string(h.offset) + ": chunk ";
  if (!is_valid_type(h.type)) {
    char hex[24];
    std::snprintf(hex, sizeof hex, "%02x %02x %02x %02x", b[0], b[1], b[2], b[3]);
    throw_bad_input(in.path(), where + "type " + hex +
                                   " is not four letters or digits (damaged "
                                   "file or not a chunk boundary)");
  }
  const std::string name = where + "'" + type_name(h.type) + "'";
  if (h.flags & ~kKnownChunkFlags)
    throw_unsupported(in.path(), name + " has flag bits 0x" + hex32(h.flags & ~kKnownChunkFlags) +
                                     " this reader does not know");
  if (auto total = in.size_hint(); total && h.size > *total)
    throw_bad_input(in.path(), name + " claims " + std::to_string(h.size) +
                                   " payload bytes, more than the whole file (" +
                                   std::to_string(*total) + " bytes)");
  if (auto left = in.remaining(); left && h.size > *left)
    throw_bad_input(in.path(), name + ": payload truncated: " + std::to_string(h.size) +
                                   " bytes declared, only " + std::to_string(*left) +
                                   " left in the file");
  return true;
}

// nlohmann-json parses any depth but dumps recursively: a deeply nested META would overflow the
// stack of whoever shows or rewrites it, so the depth is bounded here (real metadata uses ~4).
constexpr int kMaxMetaDepth = 64;
struct MetaTooDeep {};

nlohmann::json read_meta(Payload& p) {
  std::string text;
  p.read_array(text, p.left(), 1, "metadata");
  p.finish();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, [](int depth, nlohmann::json::parse_event_t, nlohmann::json&) {
      if (depth > kMaxMetaDepth) throw MetaTooDeep{};
      return true;
    });
  } catch (const nlohmann::json::exception& e) {
    p.fail(std::string("invalid JSON: ") + e.what());
  } catch (const MetaTooDeep&) {
    p.fail("the metadata JSON nests deeper than " + std::to_string(kMaxMetaDepth) + " levels");
  }
  if (!j.is_object()) p.fail("the metadata is JSON but not an object");
  return j;
}

struct Column {
  std::string name;
  uint8_t kind = 0;
  ScalarType type = ScalarType::kFloat32;
  uint8_t components = 0;
};

Column read_column_header(Payload& p, std::size_t index) {
  const std::string what = "column " + std::to_string(index);
  Column col;
  uint16_t len = get_le<uint16_t>(p.fixed<2>(what + " name length").data());
  if (len == 0) p.fail(what + " has an empty name");
  col.name.resize(len);
  p.read(col.name.data(), len, what + " name");
  if (!is_utf8(col.name)) p.fail(what + " name is not UTF-8");
  auto b = p.fixed<3>("column '" + col.name + "' descriptor");
  col.kind = b[0];
  if (col.kind != kCoreColumn && col.kind != kExtraColumn)
    p.fail("column '" + col.name + "' has unknown kind " + std::to_string(b[0]) +
           " (0 = core, 1 = extra)");
  if (!is_scalar_code(b[1]))
    p.fail("column '" + col.name + "' has unknown scalar type code " + std::to_string(b[1]));
  col.type = static_cast<ScalarType>(b[1]);
  col.components = b[2];
  return col;
}

void expect_layout(Payload& p, const Column& col, ScalarType type, uint8_t components) {
  if (col.type != type || col.components != components)
    p.fail("core column '" + col.name + "' must be " + std::string(scalar_name(type)) + " x" +
           std::to_string(components) + ", found " + std::string(scalar_name(col.type)) + " x" +
           std::to_string(col.components));
}

void read_colors(Payload& p, const Column& col, uint64_t n, SplatCloud& c) {
  if (col.components != 3 || (col.type != ScalarType::kUInt8 && col.type != ScalarType::kUInt16))
    p.fail("core column 'color' must be uint8 x3 or uint16 x3, found " +
           std::string(scalar_name(col.type)) + " x" + std::to_string(col.components));
  if (col.type == ScalarType::kUInt16) {
    p.read_array(c.colors, n, 2, "column 'color'");
    c.color_bits = 16;
    return;
  }
  std::vector<std::array<uint8_t, 3>> bytes;
  p.read_array(bytes, n, 1, "column 'color'");
  sized_in_parallel(c.colors, bytes.size());
  for_each_chunk(bytes.size(), std::size_t{1} << 16,
                 [&](std::size_t, std::size_t b, std::size_t e) {
                   for (std::size_t i = b; i < e; ++i)
                     c.colors[i] = {bytes[i][0], bytes[i][1], bytes[i][2]};
                 });
  c.color_bits = 8;
}

void read_extra(Payload& p, const Column& col, uint64_t n, SplatCloud& c) {
  if (col.components != 1)
    p.fail("extra column '" + col.name + "' has " + std::to_string(col.components) +
           " components; 1.x extras have 1");
  ExtraAttribute e(col.name, col.type);
  const std::string what = "column '" + col.name + "'";
  with_scalar_type(col.type, [&](auto zero) {
    using T = decltype(zero);
    p.check_fits(n, sizeof(T), what);
    if (p.size_known()) e.values.reserve(static_cast<std::size_t>(n));
    std::vector<unsigned char> block;
    const std::size_t per_step = kStep / sizeof(T);
    while (e.values.size() < n) {
      const std::size_t at = e.values.size();
      std::size_t k = static_cast<std::size_t>(std::min<uint64_t>(per_step, n - at));
      block.resize(k * sizeof(T));
      p.read(block.data(), block.size(), what);
      e.values.resize(at + k);
      const std::span<T> values = e.values.as<T>();
      for (std::size_t j = 0; j < k; ++j)
        values[at + j] = load_value<T>(block.data() + j * sizeof(T));
    }
  });
  c.extras.push_back(std::move(e));
}

void read_column(Payload& p, const Column& col, uint64_t n, SplatCloud& c, bool& has_position) {
  if (col.kind == kExtraColumn) return read_extra(p, col, n, c);
  const std::string what = "column '" + col.name + "'";
  if (col.name == "position") {
    expect_layout(p, col, ScalarType::kFloat32, 3);
    p.read_array(c.positions, n, 4, what);
    has_position = true;
  } else if (col.name == "normal") {
    expect_layout(p, col, ScalarType::kFloat32, 3);
    p.read_array(c.normals, n, 4, what);
  } else if (col.name == "radius") {
    expect_layout(p, col, ScalarType::kFloat32, 1);
    p.read_array(c.radii, n, 4, what);
  } else if (col.name == "color") {
    read_colors(p, col, n, c);
  } else {
    p.fail("unknown core column '" + col.name + "' (1.x knows position, normal, radius, color)");
  }
}

void check_finite(Payload& p, const std::array<double, 3>& v, const char* what) {
  for (double x : v)
    if (!std::isfinite(x)) p.fail(std::string("the ") + what + " is not finite");
}

void read_splt(Payload& p, SplatCloud& c) {
  auto h = p.fixed<kSpltFixedBytes>("the SPLT header");
  const uint64_t n = get_le<uint64_t>(h.data());
  for (std::size_t i = 0; i < 3; ++i) c.origin[i] = get_f64(h.data() + 8 + 8 * i);
  const uint32_t flags = get_le<uint32_t>(h.data() + 32);
  std::array<double, 3> viewpoint{};
  for (std::size_t i = 0; i < 3; ++i) viewpoint[i] = get_f64(h.data() + 36 + 8 * i);
  const uint32_t columns = get_le<uint32_t>(h.data() + 60);
  if (flags & ~kSpltHasViewpoint) p.fail("unknown SPLT flag bits 0x" + hex32(flags));
  if (columns > kMaxAttributes)
    p.fail(std::to_string(columns) + " columns, more than the " + std::to_string(kMaxAttributes) +
           " splatkit reads");
  if (n > p.left() / 12)
    p.fail("point count " + std::to_string(n) + " needs " +
           (n > UINT64_MAX / 12 ? "more than 2^64" : std::to_string(n * 12)) +
           " bytes of positions alone, but the payload has " + std::to_string(p.left()) + " left");

  std::set<std::pair<uint8_t, std::string>> seen;
  bool has_position = false;
  for (uint32_t i = 0; i < columns; ++i) {
    Column col = read_column_header(p, i);
    if (!seen.insert({col.kind, col.name}).second)
      p.fail("two " + std::string(col.kind == kCoreColumn ? "core" : "extra") + " columns named '" +
             col.name + "'");
    read_column(p, col, n, c, has_position);
  }
  p.finish();
  if (!has_position) p.fail("no 'position' column");
  check_finite(p, c.origin, "origin");
  if (flags & kSpltHasViewpoint) {
    check_finite(p, viewpoint, "viewpoint");
    c.viewpoint = viewpoint;
  }
  const std::size_t bad =
      first_in_chunks(c.positions.size(), std::size_t{1} << 16, [&](std::size_t i) {
        const Vec3f& q = c.positions[i];
        return !std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z);
      });
  if (bad < c.positions.size()) {
    const Vec3f& q = c.positions[bad];
    p.fail("point " + std::to_string(bad) + " has a non-finite position (" + std::to_string(q.x) +
           ", " + std::to_string(q.y) + ", " + std::to_string(q.z) + ")");
  }
}

void read_face(Payload& p, SplatCloud& c) {
  auto h = p.fixed<16>("the FACE header");
  const uint64_t faces = get_le<uint64_t>(h.data()), indices = get_le<uint64_t>(h.data() + 8);
  // The payload must be exactly 4 (F + 1) + 4 I bytes: compare without overflowing.
  const uint64_t words = p.left() / 4;
  if (p.left() % 4 != 0 || faces >= words || indices != words - faces - 1)
    p.fail(std::to_string(faces) + " faces and " + std::to_string(indices) +
           " indices do not match the " + std::to_string(p.left()) +
           " bytes of offsets and indices");
  if (indices > UINT32_MAX) p.fail(std::to_string(indices) + " indices exceed 32-bit offsets");
  p.read_array(c.face_offsets, faces + 1, 4, "face offsets");
  p.read_array(c.face_indices, indices, 4, "face indices");
  p.finish();
  if (c.face_offsets.front() != 0) p.fail("the first face offset is not 0");
  for (std::size_t f = 1; f < c.face_offsets.size(); ++f)
    if (c.face_offsets[f] < c.face_offsets[f - 1])
      p.fail("face offsets decrease at face " + std::to_string(f - 1));
  if (c.face_offsets.back() != indices) p.fail("the last face offset is not the index count");
}

// After SPLT (the splats it describes must be known), with as many entries as splats, and only
// for splats with normals and radii.
void read_elps(Payload& p, SplatCloud& c, bool after_splt) {
  if (!after_splt) p.fail("the ELPS chunk comes before the SPLT chunk it describes");
  auto h = p.fixed<8>("the ELPS header");
  const uint64_t n = get_le<uint64_t>(h.data());
  if (n != c.size())
    p.fail(std::to_string(n) + " ellipses for " + std::to_string(c.size()) + " splats");
  if (!c.has_normals() || !c.has_radii()) p.fail("ellipses for splats without normals or radii");
  if (p.left() != n * 16)
    p.fail(std::to_string(p.left()) + " bytes do not hold " + std::to_string(n) +
           " axes and minor radii (16 bytes each)");
  p.read_array(c.axes, n, 4, "ellipse axes");
  p.read_array(c.minor_radii, n, 4, "minor radii");
  p.finish();
}

RawChunk read_raw(Payload& p, const ChunkHeader& h) {
  RawChunk r;
  std::memcpy(r.type, h.type.data(), 4);
  r.flags = h.flags;
  p.read_array(r.payload, h.size, 1, "payload");
  p.finish();
  return r;
}

void check_face_indices(InputStream& in, const SplatCloud& c) {
  for (std::size_t i = 0; i < c.face_indices.size(); ++i)
    if (c.face_indices[i] >= c.size())
      throw_bad_input(in.path(), "FACE: index " + std::to_string(i) + " is " +
                                     std::to_string(c.face_indices[i]) + ", but there are only " +
                                     std::to_string(c.size()) + " splats");
}

bool is_carried_type(const ChunkType& t) {
  return std::find(kCarriedTypes.begin(), kCarriedTypes.end(), t) != kCarriedTypes.end();
}

// Reads one chunk's payload into doc; `seen` counts the once-only types.
void read_chunk(InputStream& in, const ChunkHeader& h, LoadedCloud& doc, SplatCloud& faces,
                std::set<ChunkType>& seen) {
  Payload p(in, h);
  const bool once = h.type == kMeta || h.type == kSplt || h.type == kFace || h.type == kElps;
  if (once && !seen.insert(h.type).second)
    p.fail("a second '" + type_name(h.type) + "' chunk (only one is allowed)");
  if (h.type == kElps) return read_elps(p, doc.cloud, seen.count(kSplt) != 0);
  if (h.type == kMeta) {
    doc.metadata = read_meta(p);
  } else if (h.type == kSplt) {
    read_splt(p, doc.cloud);
  } else if (h.type == kFace) {
    read_face(p, faces);
  } else if ((h.flags & kSplkChunkCritical) && !is_carried_type(h.type)) {
    throw_unsupported(in.path(), "chunk '" + type_name(h.type) + "' at byte " +
                                     std::to_string(h.offset) +
                                     " is critical and unknown to this reader (a newer splatkit "
                                     "may read it)");
  } else {
    doc.chunks.push_back(read_raw(p, h));
  }
}

// The minor version of a file holding doc's chunks: the newest "since" among the registered types
// written. Carried chunks of types this writer does not know do not raise it (their version is
// unknown here; readers of any 1.x carry them through or refuse them by name).
uint16_t minor_version_for(const LoadedCloud& doc) {
  if (doc.cloud.has_ellipses()) return 2;
  const bool since_1_1 = std::any_of(doc.chunks.begin(), doc.chunks.end(), [](const RawChunk& r) {
    return std::any_of(kSince1_1.begin(), kSince1_1.end(),
                       [&](const char* t) { return std::equal(t, t + 4, r.type); });
  });
  return since_1_1 ? 1 : 0;
}

}  // namespace

bool is_splk_magic(std::string_view first_bytes) {
  if (first_bytes.size() < 5 || first_bytes.substr(1, 4) != "SPLK") return false;
  const auto b0 = static_cast<unsigned char>(first_bytes[0]);
  return b0 == 0x89 || b0 == 0x09;
}

LoadedCloud read_splk(InputStream& in, const ReadOptions& /*options*/) {
  LoadedCloud doc;
  doc.format = "splk";
  read_file_header(in, doc);
  std::set<ChunkType> seen;
  SplatCloud faces;
  ChunkHeader h;
  std::optional<ChunkType> last;
  for (std::size_t count = 0;; ++count) {
    if (count == kMaxChunks)
      throw_bad_input(in.path(), "byte " + std::to_string(in.offset()) + ": more than " +
                                     std::to_string(kMaxChunks) +
                                     " chunks (the most a reader accepts; damaged or not a "
                                     "file splatkit wrote?)");
    if (!read_chunk_header(in, h))
      throw_bad_input(in.path(), "byte " + std::to_string(in.offset()) +
                                     ": missing END chunk: the file ends after " +
                                     (last ? "chunk '" + type_name(*last) + "'" : "the header") +
                                     " (truncated?)");
    doc.header["chunks"].push_back({{"type", type_name(h.type)},
                                    {"offset", h.offset},
                                    {"flags", h.flags},
                                    {"bytes", h.size},
                                    {"crc", hex32(h.crc)}});
    if (h.type == kEnd) {
      Payload p(in, h);
      if (h.size != 0)
        p.fail("the END chunk has a payload of " + std::to_string(h.size) + " bytes");
      p.finish();
      break;
    }
    read_chunk(in, h, doc, faces, seen);
    last = h.type;
  }
  if (!in.at_eof()) {
    auto left = in.remaining();
    throw_bad_input(in.path(), "byte " + std::to_string(in.offset()) + ": " +
                                   (left ? std::to_string(*left) + " bytes of " : std::string()) +
                                   "trailing data after the END chunk");
  }
  if (!seen.count(kSplt)) throw_bad_input(in.path(), "no SPLT chunk (the splats) before END");
  doc.cloud.face_offsets = std::move(faces.face_offsets);
  doc.cloud.face_indices = std::move(faces.face_indices);
  check_face_indices(in, doc.cloud);
  return doc;
}

void write_splk(const LoadedCloud& doc, OutputFile& out) {
  check_writable(doc, out);
  std::string meta;
  try {
    meta = doc.metadata.is_null() ? "{}" : doc.metadata.dump();
  } catch (const nlohmann::json::exception& e) {
    throw_output(out.path(), std::string("cannot encode the metadata: ") + e.what());
  }
  std::string h(reinterpret_cast<const char*>(kMagic), 8);
  put_le(h, kMajor);
  put_le(h, minor_version_for(doc));
  put_le(h, kKnownFileFlags);
  out.write(h);
  write_chunk(out, kMeta, 0, [&](PayloadSink& s) { s.put(meta); });
  write_chunk(out, kSplt, kSplkChunkCritical | kSplkChunkTiedToSplats,
              [&](PayloadSink& s) { put_splt(s, doc.cloud); });
  if (!doc.cloud.face_offsets.empty())
    write_chunk(out, kFace, kSplkChunkTiedToSplats,
                [&](PayloadSink& s) { put_face(s, doc.cloud); });
  if (doc.cloud.has_ellipses())
    write_chunk(out, kElps, kSplkChunkTiedToSplats,
                [&](PayloadSink& s) { put_elps(s, doc.cloud); });
  for (const RawChunk& r : doc.chunks)
    write_chunk(out, ChunkType{r.type[0], r.type[1], r.type[2], r.type[3]}, r.flags,
                [&](PayloadSink& s) { s.put(r.payload.data(), r.payload.size()); });
  write_chunk(out, kEnd, kSplkChunkCritical, [](PayloadSink&) {});
}

std::size_t drop_chunks_tied_to_splats(LoadedCloud& doc) {
  return std::erase_if(doc.chunks,
                       [](const RawChunk& c) { return (c.flags & kSplkChunkTiedToSplats) != 0; });
}

}  // namespace splatkit
