#include "formats/laz.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "formats/laz_chunk.h"
#include "formats/little_endian.h"
#include "splatkit/error.h"

namespace splatkit {

namespace {

using le::get32;
using le::get64;

// A chunk cannot hold more points than this per compressed byte: identical records cost LASzip's
// adaptive models about 0.01 bit each (about 800 per byte), so a larger claim is a corrupt table.
// Also what bounds the memory a forged count can make the decoder allocate.
constexpr uint64_t kMaxPointsPerByte = 1024;
// Points of a run of chunks decoded by one task (read_laz_points): enough that a run of small
// chunks costs little scheduling, few enough that a run's records stay mostly in cache on their
// way to the sink and its buffer costs few page faults.
constexpr uint64_t kRunPoints = uint64_t{1} << 15;
constexpr uint64_t kEvlrHeaderBytes = 60;

// The rest of a stream in memory, in a buffer that is not zeroed first.
struct Rest {
  std::unique_ptr<unsigned char[]> bytes;
  std::size_t size = 0;
  std::span<const unsigned char> span() const { return {bytes.get(), size}; }
};

// Reads the rest of `in`: of known size in one read (InputStream reads a large regular file's
// pieces on several threads), else in pieces into a buffer that doubles.
Rest read_rest(InputStream& in) {
  Rest r;
  std::size_t capacity = std::size_t{1} << 20;
  if (auto left = in.remaining()) capacity = static_cast<std::size_t>(*left) + 1;  // + 1: sees EOF
  r.bytes.reset(new unsigned char[capacity]);
  for (;;) {
    const std::size_t got = in.read_some(r.bytes.get() + r.size, capacity - r.size);
    r.size += got;
    if (got == 0) return r;
    if (r.size == capacity) {
      std::unique_ptr<unsigned char[]> bigger(new unsigned char[2 * capacity]);
      std::memcpy(bigger.get(), r.bytes.get(), r.size);
      r.bytes = std::move(bigger);
      capacity *= 2;
    }
  }
}

struct Chunk {
  uint64_t first_point = 0, points = 0;
  uint64_t offset = 0, bytes = 0;  // within the point data
};

// The chunks of the point data; `table_end` receives where the chunk table's coded entries end
// and `end` where the point data ends (before the 8-byte table offset a streaming LASzip
// appends), both within `data`.
std::vector<Chunk> chunk_layout(const std::string& path, const LazPointsInfo& info,
                                const laz::LaszipVlr& vlr, std::span<const unsigned char> data,
                                uint64_t& table_end, uint64_t& end_of_data) {
  if (data.size() < 8)
    throw_bad_input(path, "LAZ point data is " + std::to_string(data.size()) +
                              " bytes, too short for the chunk table offset");
  uint64_t table = get64(data.data());
  const uint64_t end = info.point_offset + data.size();
  if (table ==
      ~uint64_t{0}) {  // written by a streaming LASzip: the offset is the file's last 8 bytes
    if (data.size() < 16) throw_bad_input(path, "LAZ chunk table offset missing at the end");
    table = get64(data.data() + data.size() - 8);
    end_of_data = data.size() - 8;
  } else {
    end_of_data = data.size();
  }
  if (table < info.point_offset + 8 || table > end || end - table < 8)
    throw_bad_input(path, "LAZ chunk table offset " + std::to_string(table) +
                              " lies outside the point data (bytes " +
                              std::to_string(info.point_offset + 8) + " to " + std::to_string(end) +
                              ")");
  const uint64_t rel = table - info.point_offset;
  const uint32_t version = get32(data.data() + rel);
  const uint32_t n = get32(data.data() + rel + 4);
  if (version != 0)
    throw_unsupported(
        path, "LAZ chunk table version " + std::to_string(version) + " is not supported (0 is)");
  const uint64_t room = (rel - 8) / info.record_length;
  if (n > room)
    throw_bad_input(path, "LAZ chunk table lists " + std::to_string(n) +
                              " chunks but the point data has room for at most " +
                              std::to_string(room));
  const bool variable = vlr.chunk_size == laz::kVariableChunkSize;
  if (!variable) {
    const uint64_t expected = info.count / vlr.chunk_size + (info.count % vlr.chunk_size != 0);
    if (n != expected)
      throw_bad_input(
          path, "header says " + std::to_string(info.count) + " points, " +
                    std::to_string(expected) + " chunks of " + std::to_string(vlr.chunk_size) +
                    " points, but the chunk table lists " + std::to_string(n) + " chunks");
  }
  std::vector<laz::ChunkEntry> entries;
  std::size_t used = 0;
  try {
    entries = laz::decode_chunk_table(data.subspan(rel + 8), n, variable, &used);
  } catch (const laz::LazDataError& e) {
    throw_bad_input(path, std::string("LAZ chunk table: ") + e.what());
  }
  table_end = rel + 8 + used;
  std::vector<Chunk> chunks;
  chunks.reserve(n);
  uint64_t offset = 8, first = 0;
  for (uint32_t i = 0; i < n; ++i) {
    Chunk c;
    c.first_point = first;
    c.points =
        variable ? entries[i].points : std::min<uint64_t>(vlr.chunk_size, info.count - first);
    c.offset = offset;
    c.bytes = entries[i].bytes;
    const std::string which = "LAZ chunk " + std::to_string(i) + " of " + std::to_string(n);
    if (c.bytes < info.record_length || c.bytes > rel - offset)
      throw_bad_input(path, which + " claims " + std::to_string(c.bytes) +
                                " bytes at point-data byte " + std::to_string(offset) +
                                ", which do not fit before the chunk table (byte " +
                                std::to_string(rel) + ")");
    if (c.points == 0 || c.points > info.count - first)
      throw_bad_input(path, which + " claims " + std::to_string(c.points) +
                                " points; the header says " + std::to_string(info.count) +
                                " in all and " + std::to_string(first) + " came before");
    if (c.points > c.bytes * kMaxPointsPerByte)
      throw_bad_input(path, which + " claims " + std::to_string(c.points) + " points in " +
                                std::to_string(c.bytes) +
                                " bytes, more than LASzip can compress into them");
    offset += c.bytes;
    first += c.points;
    chunks.push_back(c);
  }
  if (first != info.count)
    throw_bad_input(path, "header says " + std::to_string(info.count) +
                              " points but the LAZ chunks hold " + std::to_string(first));
  return chunks;
}

// After the chunk table: LAS 1.4 extended VLRs (each header checked, the last ending the file),
// otherwise nothing but the one byte of look-ahead slack the chunks get too.
void check_tail(const std::string& path, const LazPointsInfo& info,
                std::span<const unsigned char> data, uint64_t table_end, uint64_t end_of_data) {
  uint64_t at = table_end;
  const char* last = "LAZ chunk table";
  if (info.evlr_count > 0) {
    if (info.evlr_start < info.point_offset + table_end ||
        info.evlr_start > info.point_offset + end_of_data)
      throw_bad_input(path, "first EVLR at byte " + std::to_string(info.evlr_start) +
                                " does not lie between the end of the LAZ chunk table (byte " +
                                std::to_string(info.point_offset + table_end) +
                                ") and the end of the file");
    at = info.evlr_start - info.point_offset;
    for (uint32_t k = 0; k < info.evlr_count; ++k) {
      if (end_of_data - at < kEvlrHeaderBytes)
        throw_bad_input(path, "EVLR " + std::to_string(k) + " of " +
                                  std::to_string(info.evlr_count) +
                                  ": unexpected end of file in its header");
      const uint64_t length = get64(data.data() + at + 20);
      at += kEvlrHeaderBytes;
      if (length > end_of_data - at)
        throw_bad_input(path, "EVLR " + std::to_string(k) + " of " +
                                  std::to_string(info.evlr_count) + " claims " +
                                  std::to_string(length) + " bytes, past the end of the file");
      at += length;
    }
    last = "EVLR";
    if (at == end_of_data) return;
  } else if (end_of_data - at <= 1) {
    return;
  }
  throw_bad_input(path, std::to_string(end_of_data - at) + " bytes of trailing data after the " +
                            last + " (file byte " + std::to_string(info.point_offset + at) + ")");
}

}  // namespace

void check_laz_vlr(const std::string& path, const LazPointsInfo& info) {
  if (!info.has_laszip_vlr)
    throw_bad_input(path, "compressed LAS (LAZ) without the LASzip VLR (user id '" +
                              std::string(laz::kLaszipUserId) + "', record " +
                              std::to_string(laz::kLaszipRecordId) + ")");
  laz::LaszipVlr vlr;
  std::string error;
  if (!laz::parse_laszip_vlr(info.laszip_vlr, vlr, error)) throw_bad_input(path, error);
  const bool v14 = info.format >= 6;
  if (!v14 && vlr.compressor == laz::kLayeredChunked)
    throw_unsupported(path, "LASzip layered compressor (3) for point data format " +
                                std::to_string(info.format) +
                                " is not supported (LASzip writes formats 0-3 with compressor 2)");
  if (v14 && vlr.compressor != laz::kLayeredChunked)
    throw_unsupported(path, "LASzip compressor " + std::to_string(vlr.compressor) +
                                " for point data format " + std::to_string(info.format) +
                                " is not supported (3, layered chunked, is)");
  if (!v14 && vlr.compressor != laz::kPointWiseChunked)
    throw_unsupported(path, "LASzip compressor " + std::to_string(vlr.compressor) +
                                " is not supported (2, point-wise chunked, is)");
  if (vlr.coder != 0)
    throw_unsupported(path, "LASzip coder " + std::to_string(vlr.coder) +
                                " is not supported (0, arithmetic, is)");
  if (vlr.chunk_size == 0) throw_bad_input(path, "LASzip chunk size is 0");
  const std::vector<laz::Item> want = laz::items_for_format(info.format, info.record_length);
  if (vlr.items.size() != want.size())
    throw_bad_input(path, "LASzip VLR lists " + std::to_string(vlr.items.size()) +
                              " items; point data format " + std::to_string(info.format) +
                              " with " + std::to_string(info.record_length) +
                              "-byte records needs " + std::to_string(want.size()));
  for (std::size_t i = 0; i < want.size(); ++i) {
    const laz::Item& got = vlr.items[i];
    if (got.type != want[i].type || got.size != want[i].size)
      throw_bad_input(path, "LASzip item " + std::to_string(i) + " is " + laz::item_name(got.type) +
                                " of " + std::to_string(got.size) + " bytes; point data format " +
                                std::to_string(info.format) + " needs " +
                                laz::item_name(want[i].type) + " of " +
                                std::to_string(want[i].size) + " bytes there");
    if (got.version != want[i].version)
      throw_unsupported(path, "LASzip item " + laz::item_name(got.type) + " version " +
                                  std::to_string(got.version) + " is not supported (" +
                                  std::to_string(want[i].version) + " is)");
  }
}

void read_laz_points(InputStream& in, const LazPointsInfo& info,
                     const std::function<void(const unsigned char*, std::size_t)>& sink) {
  const std::string& path = in.path();
  laz::LaszipVlr vlr;
  std::string error;
  laz::parse_laszip_vlr(info.laszip_vlr, vlr, error);  // checked by check_laz_vlr
  const Rest rest = read_rest(in);
  const std::span<const unsigned char> data = rest.span();
  if (info.count == 0 && data.empty()) return;
  uint64_t table_end = 0, end_of_data = 0;
  const std::vector<Chunk> chunks = chunk_layout(path, info, vlr, data, table_end, end_of_data);
  check_tail(path, info, data, table_end, end_of_data);
  if (info.count == 0) return;
  const std::size_t rl = info.record_length;
  const std::size_t workers =
      static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
  // Runs of consecutive chunks of at least kRunPoints points (one chunk when it is larger), in
  // a pipeline: runs are decoded in parallel, each into a buffer of its own, and handed to the
  // sink in file order while later runs are decoded. No batch waits for its slowest chunk (a
  // worker that is preempted holds up only its own run), and at most 4 runs per worker are in
  // flight, each with its buffer (allocated once, reused, not zeroed).
  struct Run {
    std::size_t begin = 0, end = 0;
    uint64_t points = 0;
  };
  std::vector<Run> runs;
  uint64_t most = 0;
  for (std::size_t begin = 0, end = 0; begin < chunks.size(); begin = end) {
    Run r{begin, begin, 0};
    while (r.end < chunks.size() && (r.end == begin || r.points < kRunPoints))
      r.points += chunks[r.end++].points;
    end = r.end;
    most = std::max(most, r.points);
    runs.push_back(r);
  }
  const std::size_t tokens = std::min(runs.size(), 4 * workers);
  std::vector<std::unique_ptr<unsigned char[]>> buffers;
  std::vector<unsigned char*> free_buffers;
  std::mutex free_mutex;  // the first and last stages may run at once on two threads
  std::vector<std::string> errors(chunks.size());
  struct Token {
    const Run* run = nullptr;
    unsigned char* records = nullptr;
  };
  std::size_t next_run = 0;
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, Token>(tbb::filter_mode::serial_in_order,
                                    [&](tbb::flow_control& fc) {
                                      if (next_run == runs.size()) {
                                        fc.stop();
                                        return Token{};
                                      }
                                      Token t{&runs[next_run++], nullptr};
                                      std::lock_guard lock(free_mutex);
                                      if (free_buffers.empty()) {
                                        buffers.emplace_back(new unsigned char[most * rl]);
                                        t.records = buffers.back().get();
                                      } else {
                                        t.records = free_buffers.back();
                                        free_buffers.pop_back();
                                      }
                                      return t;
                                    }) &
          tbb::make_filter<Token, Token>(
              tbb::filter_mode::parallel,
              [&](Token t) {
                const uint64_t base = chunks[t.run->begin].first_point;
                for (std::size_t i = t.run->begin; i < t.run->end; ++i) {
                  const Chunk& c = chunks[i];
                  try {
                    const std::size_t used = laz::decode_chunk(
                        data.subspan(c.offset, c.bytes), vlr.items, c.points,
                        t.records + (c.first_point - base) * rl);
                    if (c.bytes - used > 1)
                      errors[i] = std::to_string(c.bytes - used) + " of its " +
                                  std::to_string(c.bytes) + " bytes are left after its " +
                                  std::to_string(c.points) +
                                  " points (the point count or the chunk table is wrong)";
                  } catch (const laz::LazDataError& e) {
                    errors[i] = e.what();
                  }
                }
                return t;
              }) &
          tbb::make_filter<Token, void>(
              tbb::filter_mode::serial_in_order, [&](Token t) {
                for (std::size_t i = t.run->begin; i < t.run->end; ++i)
                  if (!errors[i].empty())
                    throw_bad_input(
                        path, "LAZ chunk " + std::to_string(i) + " of " +
                                  std::to_string(chunks.size()) + " (points " +
                                  std::to_string(chunks[i].first_point) + " to " +
                                  std::to_string(chunks[i].first_point + chunks[i].points - 1) +
                                  ", file byte " +
                                  std::to_string(info.point_offset + chunks[i].offset) +
                                  "): " + errors[i]);
                sink(t.records, static_cast<std::size_t>(t.run->points));
                std::lock_guard lock(free_mutex);
                free_buffers.push_back(t.records);
              }));
}

}  // namespace splatkit
