// LASzip chunks of point data formats 0-3: the point-wise version 2 models (POINT10, GPSTIME11,
// RGB12, BYTE); of formats 6-8: the layered version 3 models (laz_layered.cpp); the chunk table
// and the LASzip VLR. Layout and models: formats/laz.md.
//
// Records are LAS point records as in an uncompressed file (little-endian, record_length bytes
// each). Decoders are safe for untrusted input: they throw laz::LazDataError (no file name; the
// caller adds it) when the bytes run out or cannot have been encoded.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "formats/laz_arithmetic.h"

namespace splatkit::laz {

// LASzip item types (laszip.hpp) and compressor kinds.
enum ItemType : uint16_t {
  kItemByte = 0,
  kItemPoint10 = 6,
  kItemGpsTime11 = 7,
  kItemRgb12 = 8,
  kItemWavePacket13 = 9,
  kItemPoint14 = 10,
  kItemRgb14 = 11,
  kItemRgbNir14 = 12,
  kItemWavePacket14 = 13,
  kItemByte14 = 14,
};
enum Compressor : uint16_t {
  kNone = 0,
  kPointWise = 1,
  kPointWiseChunked = 2,
  kLayeredChunked = 3
};

inline constexpr uint32_t kVariableChunkSize = 0xFFFFFFFFu;
inline constexpr uint16_t kLaszipRecordId = 22204;
inline constexpr const char* kLaszipUserId = "laszip encoded";

struct Item {
  uint16_t type = 0, size = 0, version = 0;
};

// The LASzip VLR's payload (34 bytes + 6 per item).
struct LaszipVlr {
  uint16_t compressor = kPointWiseChunked, coder = 0;
  uint8_t version_major = 2, version_minor = 2;
  uint16_t revision = 0;
  uint32_t options = 0;
  uint32_t chunk_size = 50000;
  int64_t special_evlr_count = -1, special_evlr_offset = -1;
  std::vector<Item> items;
};

// Name of an item type for messages ("POINT10", "RGB12", ...).
std::string item_name(uint16_t type);

// Parses the payload; returns false (with `error` set) when it is too short or its item count
// disagrees with its length.
bool parse_laszip_vlr(std::span<const unsigned char> payload, LaszipVlr& vlr, std::string& error);
std::vector<unsigned char> laszip_vlr_payload(const LaszipVlr& vlr);

// The items LASzip uses for point data format 0-3 (POINT10, GPSTIME11, RGB12, BYTE; version 2)
// or 6-8 (POINT14, RGB14 or RGBNIR14, BYTE14; version 3) with `record_length` bytes (extra bytes
// become one BYTE or BYTE14 item).
std::vector<Item> items_for_format(int format, uint16_t record_length);

// Decodes `count` (>= 1) records of `items` from one chunk's bytes into `out`
// (count * record_length bytes, record_length = sum of item sizes). Returns the bytes the decoder
// consumed (a valid chunk leaves at most 1 byte: LASzip pads with 3 zero bytes where the decoder
// reads 2 or 3). Supports exactly the version-2 items that items_for_format gives.
std::size_t decode_chunk(std::span<const unsigned char> bytes, const std::vector<Item>& items,
                         uint64_t count, unsigned char* out);

// The same for layered chunks (compressor 3: POINT14, RGB14/RGBNIR14, BYTE14, version 3), which
// decode_chunk and encode_chunk call for such items. The bytes consumed are the chunk's exact size.
std::size_t decode_layered_chunk(std::span<const unsigned char> bytes,
                                 const std::vector<Item>& items, uint64_t count,
                                 unsigned char* out);
void encode_layered_chunk(const unsigned char* records, uint64_t count,
                          const std::vector<Item>& items, std::vector<unsigned char>& out);

// Appends one chunk holding `count` (>= 1) records to `out`.
void encode_chunk(const unsigned char* records, uint64_t count, const std::vector<Item>& items,
                  std::vector<unsigned char>& out);

struct ChunkEntry {
  uint64_t points = 0;  // points in the chunk
  uint64_t bytes = 0;   // compressed bytes of the chunk
};

// Decodes the arithmetic-coded part of a chunk table (after its version and count) of `chunks`
// entries; `variable` when the counts are stored too (chunk size kVariableChunkSize). `used`, when
// given, receives the bytes the decoder consumed (0 for no chunks: the coder then writes nothing).
std::vector<ChunkEntry> decode_chunk_table(std::span<const unsigned char> bytes, uint32_t chunks,
                                           bool variable, std::size_t* used = nullptr);
// Appends a complete chunk table (version 0, count, coded entries).
void encode_chunk_table(const std::vector<ChunkEntry>& chunks, bool variable,
                        std::vector<unsigned char>& out);

}  // namespace splatkit::laz
