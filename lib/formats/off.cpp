#include "formats/off.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "formats/text_numbers.h"
#include "splatkit/error.h"
#include "splatkit/position_builder.h"

namespace splatkit {

namespace {

// Smallest text of one vertex / face value ("0 "): caps the counts by the bytes left.
constexpr uint64_t kMinBytesPerValue = 2;
constexpr uint64_t kMinBytesPerFace = 8;  // "3 0 1 2\n"
constexpr std::size_t kMaxReserve = std::size_t{1} << 20;

class OffReader {
 public:
  explicit OffReader(InputStream& in) : in_(in), positions_(doc_.cloud, in.path()) {}
  LoadedCloud read();

 private:
  bool next_tokens();
  [[noreturn]] void fail_line(const std::string& what) const;
  void read_keyword();
  void read_counts();
  void read_vertex(uint64_t k);
  void read_face(uint64_t k);
  uint16_t colour(std::string_view tok, bool as_float) const;

  InputStream& in_;
  LoadedCloud doc_;
  PositionBuilder positions_;
  std::string line_;
  uint64_t line_no_ = 0;
  std::vector<std::string_view> toks_;
  std::string keyword_;
  bool normals_ = false, colors_ = false;
  uint64_t nv_ = 0, nf_ = 0, ne_ = 0;
};

void OffReader::fail_line(const std::string& what) const {
  throw_bad_input(in_.path(), "line " + std::to_string(line_no_) + ": " + what);
}

// Tokens of the next line that holds any, with '#' comments removed; false at end of file.
bool OffReader::next_tokens() {
  while (in_.read_line(line_)) {
    ++line_no_;
    std::string_view t = line_;
    auto hash = t.find('#');
    if (hash != std::string_view::npos) t = t.substr(0, hash);
    text::split(t, 0, toks_);
    if (!toks_.empty()) return true;
  }
  return false;
}

void OffReader::read_keyword() {
  if (!next_tokens()) throw_bad_input(in_.path(), "empty file (no OFF header)");
  const std::string_view kw = toks_[0];
  if (kw == "OFF" || kw == "COFF" || kw == "NOFF" || kw == "CNOFF") {
    keyword_ = std::string(kw);
  } else if (kw.size() > 3 && kw.substr(kw.size() - 3) == "OFF" &&
             kw.find_first_not_of("STCN4n") == kw.size() - 3) {
    throw_unsupported(in_.path(), "OFF variant '" + std::string(kw) +
                                      "' is not supported (OFF, COFF, NOFF, CNOFF are)");
  } else {
    fail_line("not an OFF file: header keyword is '" + std::string(kw.substr(0, 20)) + "'");
  }
  colors_ = keyword_.find('C') != std::string::npos;
  normals_ = keyword_.find('N') != std::string::npos;
  if (toks_.size() > 1 && toks_[1] == "BINARY")
    throw_unsupported(in_.path(), "binary OFF is not supported (only the text form is)");
  toks_.erase(toks_.begin());
}

void OffReader::read_counts() {
  if (toks_.empty() && !next_tokens())
    throw_bad_input(in_.path(), "unexpected end of file: no vertex/face/edge count line");
  if (toks_.size() != 3)
    fail_line("expected 3 counts (vertices faces edges), found " + std::to_string(toks_.size()) +
              " values");
  uint64_t* dst[3] = {&nv_, &nf_, &ne_};
  for (int i = 0; i < 3; ++i)
    if (!text::parse_uint64(toks_[i], *dst[i]))
      fail_line("count '" + std::string(toks_[i].substr(0, 40)) +
                "' is not a non-negative integer");
  const uint64_t per_vertex = (3 + (normals_ ? 3 : 0) + (colors_ ? 3 : 0)) * kMinBytesPerValue;
  if (auto remaining = in_.remaining()) {
    const uint64_t left = *remaining + 1;  // the last line may lack its newline
    // Each check alone first: their sum could overflow.
    if (nv_ > left / per_vertex || nf_ > left / kMinBytesPerFace ||
        nv_ * per_vertex + nf_ * kMinBytesPerFace > left)
      fail_line("header claims " + std::to_string(nv_) + " vertices and " + std::to_string(nf_) +
                " faces, more than the " + std::to_string(*remaining) + " bytes left can hold");
  }
  if (nv_ > std::numeric_limits<uint32_t>::max())
    fail_line("vertex count " + std::to_string(nv_) + " exceeds 2^32 - 1");
}

uint16_t OffReader::colour(std::string_view tok, bool as_float) const {
  double v;
  if (!text::parse_double(tok, v))
    fail_line("colour value is not a number: '" + std::string(tok.substr(0, 40)) + "'");
  if (as_float) {
    if (!(v >= 0 && v <= 1))
      fail_line("colour value '" + std::string(tok.substr(0, 40)) + "' out of range 0-1");
    return static_cast<uint16_t>(std::lround(v * 255));
  }
  if (!(v >= 0 && v <= 255))
    fail_line("colour value '" + std::string(tok.substr(0, 40)) + "' out of range 0-255");
  return static_cast<uint16_t>(v);
}

void OffReader::read_vertex(uint64_t k) {
  if (!next_tokens())
    throw_bad_input(in_.path(), "unexpected end of file after " + std::to_string(k) + " of " +
                                    std::to_string(nv_) + " vertices");
  const std::size_t base = 3 + (normals_ ? 3 : 0);
  const std::size_t n = toks_.size();
  if (colors_ ? (n != base + 3 && n != base + 4) : n != base)
    fail_line("vertex " + std::to_string(k) + ": expected " + std::to_string(base) +
              (colors_ ? " + 3 or 4 colour" : "") + " values, found " + std::to_string(n));
  double v[6];
  for (std::size_t i = 0; i < base; ++i) {
    if (!text::parse_double(toks_[i], v[i]))
      fail_line("vertex " + std::to_string(k) + ": not a number: '" +
                std::string(toks_[i].substr(0, 40)) + "'");
    if (!std::isfinite(v[i]))
      fail_line("vertex " + std::to_string(k) + ": NaN or infinite " +
                (i < 3 ? "coordinate" : "normal"));
    // Stored as float32: beyond its range is an error, not an infinity.
    if (!fits_float(v[i]))
      fail_line("vertex " + std::to_string(k) + ": " + (i < 3 ? "coordinate" : "normal") + " '" +
                std::string(toks_[i].substr(0, 40)) +
                "' is beyond float range (magnitude above 3.4e38)");
  }
  SplatCloud& c = doc_.cloud;
  positions_.add({v[0], v[1], v[2]});
  if (normals_)
    c.normals.push_back(
        {static_cast<float>(v[3]), static_cast<float>(v[4]), static_cast<float>(v[5])});
  if (colors_) {
    // Integers are 0-255; any value written with a '.' or exponent makes the vertex 0-1 floats.
    bool as_float = false;
    for (std::size_t i = base; i < n; ++i) as_float |= !text::is_integer_literal(toks_[i]);
    c.colors.push_back({colour(toks_[base], as_float), colour(toks_[base + 1], as_float),
                        colour(toks_[base + 2], as_float)});
    if (n == base + 4) colour(toks_[base + 3], as_float);  // alpha: checked, not kept
  }
}

void OffReader::read_face(uint64_t k) {
  if (!next_tokens())
    throw_bad_input(in_.path(), "unexpected end of file after " + std::to_string(k) + " of " +
                                    std::to_string(nf_) + " faces");
  uint64_t n = 0;
  if (!text::parse_uint64(toks_[0], n))
    fail_line("face " + std::to_string(k) + ": vertex count '" +
              std::string(toks_[0].substr(0, 40)) + "' is not a non-negative integer");
  if (n < 3)
    fail_line("face " + std::to_string(k) + " has " + std::to_string(n) +
              " vertices (at least 3 needed)");
  // After the indices an optional face colour (1-4 values) may follow; it is ignored.
  if (toks_.size() < n + 1 || toks_.size() > n + 5)
    fail_line("face " + std::to_string(k) + ": expected " + std::to_string(n) +
              " vertex indices (+ up to 4 colour values), found " +
              std::to_string(toks_.size() - 1) + " values");
  SplatCloud& c = doc_.cloud;
  if (c.face_indices.size() + n > std::numeric_limits<uint32_t>::max())
    fail_line("more than 2^32 - 1 face indices in total");
  for (uint64_t i = 1; i <= n; ++i) {
    uint64_t idx = 0;
    if (!text::parse_uint64(toks_[i], idx))
      fail_line("face " + std::to_string(k) + ": vertex index '" +
                std::string(toks_[i].substr(0, 40)) + "' is not a non-negative integer");
    if (idx >= nv_)
      fail_line("face " + std::to_string(k) + ": vertex index " + std::to_string(idx) +
                " out of range (" + std::to_string(nv_) + " vertices)");
    c.face_indices.push_back(static_cast<uint32_t>(idx));
  }
  c.face_offsets.push_back(static_cast<uint32_t>(c.face_indices.size()));
}

LoadedCloud OffReader::read() {
  read_keyword();
  read_counts();
  SplatCloud& c = doc_.cloud;
  const std::size_t reserve_v = static_cast<std::size_t>(std::min<uint64_t>(nv_, kMaxReserve));
  c.positions.reserve(reserve_v);
  if (normals_) c.normals.reserve(reserve_v);
  if (colors_) c.colors.reserve(reserve_v);
  for (uint64_t k = 0; k < nv_; ++k) read_vertex(k);
  positions_.finish();
  if (nf_ > 0) {
    c.face_offsets.reserve(static_cast<std::size_t>(std::min<uint64_t>(nf_, kMaxReserve)) + 1);
    c.face_offsets.push_back(0);
  }
  for (uint64_t k = 0; k < nf_; ++k) read_face(k);
  if (next_tokens()) fail_line("trailing data after the last face");
  doc_.header = {{"keyword", keyword_}, {"vertices", nv_}, {"faces", nf_}, {"edges", ne_}};
  return std::move(doc_);
}

}  // namespace

LoadedCloud read_off(InputStream& in, const ReadOptions& options) { return OffReader(in).read(); }

void write_off(const SplatCloud& cloud, OutputFile& out) {
  std::string s = std::string(cloud.has_colors() ? "C" : "") + (cloud.has_normals() ? "N" : "") +
                  "OFF\n" + std::to_string(cloud.size()) + " " +
                  std::to_string(cloud.face_count()) + " 0\n";
  auto flush_if_big = [&] {
    if (s.size() > (1u << 16)) {
      out.write(s);
      s.clear();
    }
  };
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      if (k) s += ' ';
      text::append_coordinate(s, cloud.origin[k], cloud.positions[i][k]);
    }
    if (cloud.has_normals())
      for (int k = 0; k < 3; ++k) {
        s += ' ';
        text::append_shortest(s, cloud.normals[i][k]);
      }
    if (cloud.has_colors()) {
      for (int k = 0; k < 3; ++k) {
        uint32_t v = cloud.colors[i][k];
        if (cloud.color_bits == 16) v = (v * 255 + 32767) / 65535;
        s += ' ';
        s += std::to_string(v);
      }
      s += " 255";
    }
    s += '\n';
    flush_if_big();
  }
  for (std::size_t f = 0; f < cloud.face_count(); ++f) {
    s += std::to_string(cloud.face_offsets[f + 1] - cloud.face_offsets[f]);
    for (uint32_t j = cloud.face_offsets[f]; j < cloud.face_offsets[f + 1]; ++j) {
      s += ' ';
      s += std::to_string(cloud.face_indices[j]);
    }
    s += '\n';
    flush_if_big();
  }
  out.write(s);
}

}  // namespace splatkit
