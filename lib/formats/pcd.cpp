#include "formats/pcd.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "formats/pcl_pcd.h"
#include "formats/text_numbers.h"
#include "splatkit/error.h"
#include "splatkit/extra_values.h"
#include "splatkit/position_builder.h"
#include "splatkit/remove_on_signal.h"

namespace splatkit {

namespace {

// PCL computes POINTS * point_step in 32-bit arithmetic and allocates it before reading: keep the
// data below 2^31 bytes. One point may hold at most 1 MiB (a COUNT of 10^9 is not a point).
constexpr uint64_t kMaxDataBytes = (uint64_t{1} << 31) - 1;
constexpr uint64_t kMaxPointStep = uint64_t{1} << 20;
constexpr std::size_t kMaxFields = 4096;
// LZF expands at most 264 bytes per 3-byte back reference; anything claiming more is corrupt.
constexpr uint64_t kMaxLzfRatio = 100;

struct PcdField {
  std::string name;
  int size = 4;
  char type = 'F';
  uint64_t count = 1;
};

struct PcdHeader {
  std::string version;
  std::vector<PcdField> fields;
  uint64_t width = 0, height = 1, points = 0;
  bool has_width = false, has_height = false, has_points = false;
  std::array<double, 7> viewpoint{0, 0, 0, 1, 0, 0, 0};
  std::string data;
  uint64_t point_step = 0;
};

// Everything the validator consumes is copied here when the input is not a regular file, so that
// PCL (which only reads paths) gets the same bytes. Removed on destruction, and by SIGINT, SIGTERM
// or SIGHUP (RemoveOnSignal).
class SpillFile {
 public:
  SpillFile() {
    const char* dir = std::getenv("TMPDIR");
    path_ = std::string(dir && *dir ? dir : "/tmp") + "/splatkit-pcd-XXXXXX";
    fd_ = ::mkstemp(path_.data());
    if (fd_ < 0)
      throw_output(path_, std::string("cannot create temporary file: ") + std::strerror(errno));
    remove_on_signal_.emplace(path_);
  }
  ~SpillFile() {
    if (fd_ >= 0) ::close(fd_);
    ::unlink(path_.c_str());
  }
  SpillFile(const SpillFile&) = delete;
  SpillFile& operator=(const SpillFile&) = delete;

  void write(const void* data, std::size_t n) {
    const char* p = static_cast<const char*>(data);
    while (n > 0) {
      ssize_t w = ::write(fd_, p, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0)
        throw_output(path_, std::string("cannot write temporary file: ") + std::strerror(errno));
      p += w;
      n -= static_cast<std::size_t>(w);
    }
  }
  void close() {
    if (::close(fd_) != 0)
      throw_output(path_, std::string("cannot close temporary file: ") + std::strerror(errno));
    fd_ = -1;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int fd_ = -1;
  std::optional<RemoveOnSignal> remove_on_signal_;
};

// Walks an LZF stream (the format of PCL's lzf.cpp) without producing output: every back
// reference must point into what was already produced, the output must not overrun the declared
// size and must end exactly there. Fed in chunks as the bytes stream past.
class LzfChecker {
 public:
  LzfChecker(const InputStream& in, uint64_t expected) : in_(in), expected_(expected) {}

  void feed(const unsigned char* p, std::size_t n) {
    for (std::size_t i = 0; i < n;) {
      if (state_ == kLiteral) {
        const std::size_t k = static_cast<std::size_t>(std::min<uint64_t>(pending_, n - i));
        i += k;
        pending_ -= k;
        if (pending_ == 0) state_ = kControl;
        continue;
      }
      step(p[i++]);
    }
  }

  void finish() const {
    if (state_ != kControl)
      fail("the LZF stream ends inside a " +
           std::string(state_ == kLiteral ? "literal run" : "back reference"));
    if (produced_ != expected_)
      fail("the LZF stream decompresses to " + std::to_string(produced_) + " bytes, not " +
           std::to_string(expected_));
  }

 private:
  enum State { kControl, kLiteral, kLength, kOffset };

  void step(unsigned char b) {
    switch (state_) {
      case kControl:
        if (b < 32) {
          pending_ = b + 1u;
          grow(pending_);
          state_ = kLiteral;
        } else {
          length_ = b >> 5;
          offset_high_ = b & 31u;
          state_ = length_ == 7 ? kLength : kOffset;
        }
        break;
      case kLength:
        length_ += b;
        state_ = kOffset;
        break;
      case kOffset: {
        const uint64_t distance = (uint64_t{offset_high_} << 8) + b + 1;
        if (distance > produced_) fail("an LZF back reference points before the start");
        grow(length_ + 2);
        state_ = kControl;
        break;
      }
      case kLiteral:
        break;
    }
  }

  void grow(uint64_t n) {
    produced_ += n;
    if (produced_ > expected_)
      fail("the LZF stream decompresses to more than " + std::to_string(expected_) + " bytes");
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw_bad_input(in_.path(), "binary_compressed: " + what);
  }

  const InputStream& in_;
  uint64_t expected_;
  uint64_t produced_ = 0, pending_ = 0;
  uint32_t length_ = 0, offset_high_ = 0;
  State state_ = kControl;
};

class PcdValidator {
 public:
  PcdValidator(InputStream& in, SpillFile* spill) : in_(in), spill_(spill) {}
  PcdHeader read_header();
  void check_body(const PcdHeader& h);

 private:
  bool next_line();
  [[noreturn]] void fail_line(const std::string& what) const;
  uint64_t parse_count(std::string_view tok, const char* what) const;
  void parse_keyword(PcdHeader& h, std::string_view key, int& last);
  void check_ascii(const PcdHeader& h);
  void check_binary(uint64_t expected, LzfChecker* lzf = nullptr);
  void check_compressed(const PcdHeader& h);
  void check_binary_start();
  void copy_bytes(uint64_t n, const char* what, LzfChecker* lzf = nullptr);

  InputStream& in_;
  SpillFile* spill_;
  int seen_ = 0;  // bit per Keyword
  std::string line_;
  uint64_t line_no_ = 0;
  std::vector<std::string_view> toks_;
};

void PcdValidator::fail_line(const std::string& what) const {
  throw_bad_input(in_.path(), "line " + std::to_string(line_no_) + ": " + what);
}

bool PcdValidator::next_line() {
  if (!in_.read_line(line_)) return false;
  ++line_no_;
  if (spill_) {
    spill_->write(line_.data(), line_.size());
    spill_->write("\n", 1);
  }
  return true;
}

uint64_t PcdValidator::parse_count(std::string_view tok, const char* what) const {
  uint64_t v = 0;
  if (!text::parse_uint64(tok, v))
    fail_line(std::string(what) + " '" + std::string(tok.substr(0, 40)) +
              "' is not a non-negative integer");
  return v;
}

// The header keywords in the one order PCD allows (DATA, which ends the header, comes last).
constexpr std::string_view kKeywords[] = {"VERSION", "FIELDS", "SIZE",      "TYPE",  "COUNT",
                                          "WIDTH",   "HEIGHT", "VIEWPOINT", "POINTS"};
enum Keyword { kVersion, kFields, kSize, kType, kCount, kWidth, kHeight, kViewpoint, kPoints };

void PcdValidator::parse_keyword(PcdHeader& h, std::string_view key, int& last) {
  int kw = -1;
  for (int i = 0; i < 9; ++i)
    if (key == kKeywords[i]) kw = i;
  if (kw < 0) fail_line("unknown header keyword '" + std::string(key.substr(0, 40)) + "'");
  if (kw <= last)
    fail_line(std::string(key) +
              " repeated or out of order (PCD order: VERSION FIELDS SIZE TYPE "
              "COUNT WIDTH HEIGHT VIEWPOINT POINTS DATA)");
  last = kw;
  // PCL needs SIZE before TYPE before COUNT, and the point size before WIDTH and POINTS.
  const int needs = kw == kSize ? kFields : kw == kType ? kSize : kw >= kCount ? kType : -1;
  if (needs >= 0 && !(seen_ & (1 << needs)))
    fail_line(std::string(key) + " before " + std::string(kKeywords[needs]));
  seen_ |= 1 << kw;
  const std::size_t n = toks_.size() - 1;
  auto arg = [&](std::size_t i) { return toks_[i + 1]; };
  auto per_field = [&] {
    if (h.fields.empty()) fail_line(std::string(key) + " before FIELDS");
    if (n != h.fields.size())
      fail_line(std::string(key) + " has " + std::to_string(n) + " values for " +
                std::to_string(h.fields.size()) + " fields");
  };
  switch (kw) {
    case kVersion:
      if (n != 1) fail_line("VERSION needs one value");
      h.version = std::string(arg(0));
      if (h.version != "0.7" && h.version != ".7" && h.version != "0.6" && h.version != ".6" &&
          h.version != "0.5" && h.version != ".5")
        throw_unsupported(in_.path(), "PCD version '" + std::string(arg(0).substr(0, 20)) +
                                          "' is not supported (0.5-0.7 are)");
      break;
    case kFields:
      if (n == 0) fail_line("FIELDS names no field");
      if (n > kMaxFields) fail_line("more than " + std::to_string(kMaxFields) + " fields");
      for (std::size_t i = 0; i < n; ++i) {
        for (unsigned char ch : arg(i))
          if (ch < 0x20 || ch >= 0x7f) fail_line("field name with a control or non-ASCII byte");
        for (const auto& f : h.fields)
          if (f.name == arg(i) && f.name != "_") fail_line("field '" + f.name + "' named twice");
        h.fields.push_back({std::string(arg(i)), 4, 'F', 1});
      }
      break;
    case kSize:
      per_field();
      for (std::size_t i = 0; i < n; ++i) {
        uint64_t v = parse_count(arg(i), "SIZE");
        if (v != 1 && v != 2 && v != 4 && v != 8)
          fail_line("SIZE " + std::to_string(v) + " is not 1, 2, 4 or 8");
        h.fields[i].size = static_cast<int>(v);
      }
      break;
    case kType:
      per_field();
      for (std::size_t i = 0; i < n; ++i) {
        auto t = arg(i);
        if (t != "F" && t != "I" && t != "U")
          fail_line("TYPE '" + std::string(t.substr(0, 20)) + "' is not F, I or U");
        h.fields[i].type = t[0];
        if (t[0] == 'F' && h.fields[i].size != 4 && h.fields[i].size != 8)
          fail_line("field '" + h.fields[i].name + "': float of size " +
                    std::to_string(h.fields[i].size));
      }
      break;
    case kCount:
      per_field();
      for (std::size_t i = 0; i < n; ++i) {
        uint64_t v = parse_count(arg(i), "COUNT");
        if (v == 0 || v > kMaxPointStep) fail_line("COUNT " + std::to_string(v) + " out of range");
        h.fields[i].count = v;
      }
      break;
    case kWidth:
    case kHeight:
    case kPoints: {
      if (n != 1) fail_line(std::string(key) + " needs one value");
      uint64_t v = parse_count(arg(0), kKeywords[kw].data());
      if (v > std::numeric_limits<uint32_t>::max())
        fail_line(std::string(key) + " exceeds 2^32 - 1");
      (kw == kWidth ? h.width : kw == kHeight ? h.height : h.points) = v;
      (kw == kWidth ? h.has_width : kw == kPoints ? h.has_points : h.has_height) = true;
      break;
    }
    case kViewpoint:
      if (n != 7) fail_line("VIEWPOINT needs 7 values (tx ty tz qw qx qy qz)");
      for (std::size_t i = 0; i < 7; ++i)
        if (!text::parse_double(arg(i), h.viewpoint[i]) || !std::isfinite(h.viewpoint[i]))
          fail_line("VIEWPOINT value '" + std::string(arg(i).substr(0, 40)) +
                    "' is not a finite number");
      break;
  }
}

// x, y and z must be single values of at least 4 bytes: PCL reads them as float when it checks
// the cloud for NaN, whatever their declared type.
void check_xyz_fields(const InputStream& in, const PcdHeader& h) {
  for (const char* name : {"x", "y", "z"}) {
    const PcdField* f = nullptr;
    for (const auto& g : h.fields)
      if (g.name == name) f = &g;
    if (!f) throw_bad_input(in.path(), "no x, y and z fields");
    if (f->count != 1 || f->size < 4)
      throw_bad_input(in.path(),
                      std::string("field '") + name + "' must be one value of 4 or 8 bytes");
  }
}

PcdHeader PcdValidator::read_header() {
  PcdHeader h;
  int last = -1;
  for (;;) {
    if (!next_line())
      throw_bad_input(in_.path(), "unexpected end of file in the PCD header (no DATA line)");
    if (line_.empty()) continue;
    std::string_view t = text::trim(line_);
    // PCL skips empty lines but ends its header at a line of spaces.
    if (t.empty()) fail_line("line of only spaces in the header");
    if (t.front() == '#') continue;
    // PCL splits header words at space, tab and CR but reads numbers at any white space: other
    // control characters would make the two disagree on the field count.
    for (char ch : t)
      if (static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\r')
        fail_line("control character in a header line");
    text::split(t, 0, toks_);
    if (toks_[0] == "DATA") {
      if (toks_.size() != 2) fail_line("DATA needs one value (ascii, binary or binary_compressed)");
      h.data = std::string(toks_[1]);
      if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
        fail_line("unknown DATA encoding '" + std::string(toks_[1].substr(0, 40)) + "'");
      break;
    }
    parse_keyword(h, toks_[0], last);
  }
  if (!(seen_ & (1 << kType))) fail_line("the header has no FIELDS, SIZE and TYPE lines");
  if (!h.has_width) fail_line("the header has no WIDTH line");
  if (!h.has_points) fail_line("the header has no POINTS line");
  if (h.width * h.height != h.points)
    fail_line("WIDTH x HEIGHT = " + std::to_string(h.width) + " x " + std::to_string(h.height) +
              " differs from POINTS " + std::to_string(h.points));
  for (const auto& f : h.fields) h.point_step += f.count * static_cast<uint64_t>(f.size);
  if (h.point_step > kMaxPointStep)
    fail_line("a point of " + std::to_string(h.point_step) + " bytes is too large");
  if (h.points > kMaxDataBytes / h.point_step)
    fail_line("POINTS " + std::to_string(h.points) + " of " + std::to_string(h.point_step) +
              " bytes exceed the 2 GiB that PCL can read");
  check_xyz_fields(in_, h);
  return h;
}

void PcdValidator::copy_bytes(uint64_t n, const char* what, LzfChecker* lzf) {
  if (!spill_ && !lzf) return in_.skip(n, what);
  char buf[1 << 16];
  while (n > 0) {
    const std::size_t k = static_cast<std::size_t>(std::min<uint64_t>(n, sizeof buf));
    in_.read(buf, k, what);
    if (spill_) spill_->write(buf, k);
    if (lzf) lzf->feed(reinterpret_cast<const unsigned char*>(buf), k);
    n -= k;
  }
}

// Exactly `expected` bytes of data, then nothing but zero bytes: PCL's own writer pads binary
// files (it sizes them for mmap), so zero padding is part of the format as written in practice.
void PcdValidator::check_binary(uint64_t expected, LzfChecker* lzf) {
  if (auto left = in_.remaining(); left && *left < expected)
    in_.fail("binary data truncated: " + std::to_string(expected) + " bytes expected, " +
             std::to_string(*left) + " left");
  copy_bytes(expected, "binary point data", lzf);
  if (lzf) lzf->finish();
  char buf[1 << 16];
  while (std::size_t n = in_.read_some(buf, sizeof buf)) {
    for (std::size_t i = 0; i < n; ++i)
      if (buf[i] != 0)
        throw_bad_input(in_.path(), "byte " + std::to_string(in_.offset() - n + i) +
                                        ": trailing data after the binary points");
  }
}

void PcdValidator::check_compressed(const PcdHeader& h) {
  unsigned char sizes[8];
  in_.read(sizes, 8, "binary_compressed sizes");
  if (spill_) spill_->write(sizes, 8);
  auto u32 = [&](int o) {
    return static_cast<uint32_t>(sizes[o]) | static_cast<uint32_t>(sizes[o + 1]) << 8 |
           static_cast<uint32_t>(sizes[o + 2]) << 16 | static_cast<uint32_t>(sizes[o + 3]) << 24;
  };
  const uint64_t compressed = u32(0), uncompressed = u32(4);
  const uint64_t expected = h.points * h.point_step;
  if (uncompressed != expected)
    in_.fail("binary_compressed: uncompressed size " + std::to_string(uncompressed) +
             " differs from POINTS x point size = " + std::to_string(expected));
  if (expected > 0 && compressed == 0) in_.fail("binary_compressed: compressed size is zero");
  if (uncompressed > compressed * kMaxLzfRatio + 64)
    in_.fail("binary_compressed: compressed size " + std::to_string(compressed) +
             " is too small for " + std::to_string(uncompressed) + " bytes");
  LzfChecker lzf(in_, uncompressed);
  check_binary(compressed, &lzf);
}

void PcdValidator::check_ascii(const PcdHeader& h) {
  uint64_t values_per_line = 0;
  for (const auto& f : h.fields) values_per_line += f.count;
  // "0 0 0\n" is the shortest line; the last one may lack its newline.
  if (auto left = in_.remaining(); left && h.points > (*left + 1) / (2 * values_per_line))
    in_.fail("POINTS " + std::to_string(h.points) + " cannot fit in the " + std::to_string(*left) +
             " bytes left");
  uint64_t seen = 0;
  while (next_line()) {
    if (line_.empty()) continue;
    std::string_view t = text::trim(line_);
    if (t.empty()) fail_line("line of only spaces among the points");
    if (seen == h.points)
      fail_line("trailing data after the last of " + std::to_string(h.points) + " points");
    // PCL splits ascii lines at space, tab and CR only.
    toks_.clear();
    for (std::size_t i = 0; i < t.size();) {
      std::size_t e = t.find_first_of(" \t\r", i);
      if (e == std::string_view::npos) e = t.size();
      if (e > i) toks_.push_back(t.substr(i, e - i));
      i = e + 1;
    }
    if (toks_.size() != values_per_line)
      fail_line("expected " + std::to_string(values_per_line) + " values, found " +
                std::to_string(toks_.size()));
    double v;
    for (auto tok : toks_)
      if (!text::parse_double(tok, v))
        fail_line("not a number: '" + std::string(tok.substr(0, 40)) + "'");
    ++seen;
  }
  if (seen < h.points)
    throw_bad_input(in_.path(), "unexpected end of file after " + std::to_string(seen) + " of " +
                                    std::to_string(h.points) + " points");
}

bool is_c_space(char c) { return c == ' ' || (c >= '\t' && c <= '\r'); }

// PCL goes on reading header lines after DATA (skipping blank, '#' and VERSION lines) until one
// it does not know. A binary body that starts with what PCL takes for a header line (POINTS,
// DATA, ...) would resize its cloud or move its data offset: reject it.
void PcdValidator::check_binary_start() {
  constexpr std::size_t kWindow = std::size_t{1} << 16;
  static constexpr std::string_view kPrefixes[] = {"FIELDS", "COLUMNS", "SIZE",   "TYPE",
                                                   "COUNT",  "WIDTH",   "HEIGHT", "VIEWPOINT",
                                                   "POINTS", "DATA"};
  const std::string_view w = in_.peek(kWindow);
  for (std::size_t pos = 0; pos < w.size();) {
    const std::size_t nl = w.find('\n', pos);
    if (nl == std::string_view::npos && w.size() == kWindow)
      in_.fail("binary data starts with 64 KiB of text lines that PCL would read as header");
    const std::string_view line = w.substr(pos, nl == std::string_view::npos ? w.npos : nl - pos);
    pos = nl == std::string_view::npos ? w.size() : nl + 1;
    if (line.empty()) continue;
    std::size_t b = 0;
    while (b < line.size() && is_c_space(line[b])) ++b;
    std::size_t e = b;
    while (e < line.size() && !is_c_space(line[e])) ++e;
    const std::string_view tok = line.substr(b, e - b);
    if (tok.substr(0, 1) == "#" || tok.substr(0, 7) == "VERSION") continue;
    for (auto kw : kPrefixes)
      if (tok.substr(0, kw.size()) == kw)
        in_.fail("binary data starts with a line that PCL would read as a header line ('" +
                 std::string(kw) + "')");
    return;
  }
}

void PcdValidator::check_body(const PcdHeader& h) {
  if (h.data == "ascii") return check_ascii(h);
  check_binary_start();
  if (h.data == "binary") return check_binary(h.points * h.point_step);
  check_compressed(h);
}

// PCL's reader takes a path: a regular file is read in place; anything else is spilled.
bool readable_in_place(const InputStream& in) {
  if (in.path() == "-" || in.offset() != 0 || !in.size_hint()) return false;
  struct stat st {};
  return ::stat(in.path().c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
         static_cast<uint64_t>(st.st_size) == *in.size_hint();
}

double load(const uint8_t* p, ScalarType type) {
  return visit_scalar_type(type, [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  });
}

// Bytes of one value of the field's type, 0 for a type splatkit does not read.
std::size_t type_size(const PclField& f) { return f.type ? scalar_size(*f.type) : 0; }

// Maps PCL's fields onto the cloud: x y z, normal_*, packed rgb/rgba, the rest as extras.
class FieldMapper {
 public:
  FieldMapper(const std::string& file, const PclRecords& pc) : file_(file), pc_(pc) {}
  void map(SplatCloud& c);

 private:
  const PclField* find(const char* name) const {
    for (const auto& f : pc_.fields)
      if (f.name == name && f.count == 1) return &f;
    return nullptr;
  }
  void check_fields() const;

  const std::string& file_;
  const PclRecords& pc_;
};

void FieldMapper::check_fields() const {
  const uint64_t n = static_cast<uint64_t>(pc_.width) * pc_.height;
  if (pc_.data.size() != n * pc_.point_step)
    throw_bad_input(file_, "PCL returned " + std::to_string(pc_.data.size()) + " bytes for " +
                               std::to_string(n) + " points of " + std::to_string(pc_.point_step));
  for (const auto& f : pc_.fields)
    if (type_size(f) == 0 || uint64_t{f.offset} + type_size(f) * uint64_t{f.count} > pc_.point_step)
      throw_bad_input(file_, "field '" + f.name + "' does not fit in the point record");
}

void FieldMapper::map(SplatCloud& c) {
  check_fields();
  const PclField* xyz[3] = {find("x"), find("y"), find("z")};
  if (!xyz[0] || !xyz[1] || !xyz[2]) throw_bad_input(file_, "no x, y and z fields");
  const PclField* nrm[3] = {find("normal_x"), find("normal_y"), find("normal_z")};
  const bool has_normals = nrm[0] && nrm[1] && nrm[2];
  const PclField* rgb = find("rgb");
  if (!rgb) rgb = find("rgba");
  if (rgb && type_size(*rgb) != 4) rgb = nullptr;

  struct Slot {
    const PclField* f;
    uint32_t k;
  };
  std::vector<Slot> slots;
  for (const auto& f : pc_.fields) {
    bool core = &f == xyz[0] || &f == xyz[1] || &f == xyz[2] || &f == rgb ||
                (has_normals && (&f == nrm[0] || &f == nrm[1] || &f == nrm[2]));
    if (core || f.name == "_") continue;
    for (uint32_t k = 0; k < f.count; ++k) {
      slots.push_back({&f, k});
      c.extras.push_back({f.count == 1 ? f.name : f.name + "_" + std::to_string(k), *f.type});
    }
  }

  const std::size_t n = static_cast<std::size_t>(pc_.width) * pc_.height;
  PositionBuilder positions(c, file_);
  for (std::size_t i = 0; i < n; ++i) {
    const uint8_t* rec = pc_.data.data() + i * pc_.point_step;
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k) p[k] = load(rec + xyz[k]->offset, *xyz[k]->type);
    // One policy in every reader: a point without a position is refused, never dropped (an
    // organised cloud's missing returns too: PCL's removeNaNFromPointCloud drops them first).
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(p[k]))
        throw_bad_input(file_, "point " + std::to_string(i) + ": NaN or infinite coordinate (" +
                                   "xyz"[k] + " = " + std::to_string(p[k]) + ")");
    for (double x : p)
      if (!fits_float(x))
        throw_bad_input(file_, "point " + std::to_string(i) + ": coordinate " + std::to_string(x) +
                                   " is beyond float range");
    positions.add(p);
    if (has_normals) {
      Vec3f v;
      for (int k = 0; k < 3; ++k)
        v[k] = static_cast<float>(load(rec + nrm[k]->offset, *nrm[k]->type));
      // A failed normal estimate is NaN in PCL; keep the point with a zero normal.
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) v = {0, 0, 0};
      c.normals.push_back(v);
    }
    if (rgb) {
      uint32_t packed;
      std::memcpy(&packed, rec + rgb->offset, 4);
      c.colors.push_back({static_cast<uint16_t>((packed >> 16) & 255),
                          static_cast<uint16_t>((packed >> 8) & 255),
                          static_cast<uint16_t>(packed & 255)});
    }
    for (std::size_t s = 0; s < slots.size(); ++s) {
      const auto& f = *slots[s].f;
      c.extras[s].values.push_back(load(rec + f.offset + slots[s].k * type_size(f), *f.type));
    }
  }
  positions.finish();
}

nlohmann::json header_json(const PcdHeader& h) {
  nlohmann::json fields = nlohmann::json::array();
  for (const auto& f : h.fields)
    fields.push_back(
        {{"name", f.name}, {"size", f.size}, {"type", std::string(1, f.type)}, {"count", f.count}});
  return {{"version", h.version},    {"fields", fields},   {"width", h.width},
          {"height", h.height},      {"points", h.points}, {"data", h.data},
          {"viewpoint", h.viewpoint}};
}

}  // namespace

LoadedCloud read_pcd(InputStream& in, const ReadOptions& options) {
  std::optional<SpillFile> spill;
  if (!readable_in_place(in)) spill.emplace();
  PcdValidator validator(in, spill ? &*spill : nullptr);
  PcdHeader h = validator.read_header();
  validator.check_body(h);
  if (spill) spill->close();

  LoadedCloud doc;
  if (h.points > 0) {
    PclRecords pc;
    const std::string why = pcl_pcd(in.path()).read(spill ? spill->path() : in.path(), pc);
    if (!why.empty()) throw_bad_input(in.path(), why);
    FieldMapper(in.path(), pc).map(doc.cloud);
  }
  if (h.viewpoint[0] != 0 || h.viewpoint[1] != 0 || h.viewpoint[2] != 0)
    doc.cloud.viewpoint = std::array<double, 3>{h.viewpoint[0], h.viewpoint[1], h.viewpoint[2]};
  doc.header = header_json(h);
  return doc;
}

}  // namespace splatkit
