// Number parsing and printing shared by the text formats (XYZ, OFF): locale-free, allocation-free.
//
// Parsing uses std::from_chars (no locale, no errno); printing gives the shortest decimal that
// reads back to the same value, so text output round-trips exactly.
#pragma once

#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace splatkit::text {

// Whole token as a double; leading '+' allowed (from_chars rejects it). False when the token is
// not a number or has trailing characters. "nan"/"inf" parse (callers reject them where needed).
inline bool parse_double(std::string_view tok, double& out) {
  if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
  if (tok.empty()) return false;
  auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && end == tok.data() + tok.size();
}

// Whole token as a non-negative decimal integer (no sign, no exponent).
inline bool parse_uint64(std::string_view tok, uint64_t& out) {
  if (tok.empty()) return false;
  auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return ec == std::errc() && end == tok.data() + tok.size();
}

// True for "12", "-3", "+7": digits only, no '.' or exponent.
inline bool is_integer_literal(std::string_view tok) {
  if (!tok.empty() && (tok.front() == '+' || tok.front() == '-')) tok.remove_prefix(1);
  if (tok.empty()) return false;
  for (char c : tok)
    if (c < '0' || c > '9') return false;
  return true;
}

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Splits `line` at whitespace (sep == 0) or at `sep` (spaces around each field trimmed) into
// `out` (cleared first; its capacity is reused from line to line).
inline void split(std::string_view line, char sep, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  const std::size_t len = line.size();
  if (sep == 0) {
    for (;;) {
      while (i < len && is_space(line[i])) ++i;
      if (i == len) return;
      std::size_t b = i;
      while (i < len && !is_space(line[i])) ++i;
      out.push_back(line.substr(b, i - b));
    }
  }
  for (;;) {
    std::size_t e = line.find(sep, i);
    if (e == std::string_view::npos) e = len;
    std::size_t b = i, f = e;
    while (b < f && is_space(line[b])) ++b;
    while (f > b && is_space(line[f - 1])) --f;
    out.push_back(line.substr(b, f - b));
    if (e == len) return;
    i = e + 1;
  }
}

// `line` without leading and trailing whitespace.
inline std::string_view trim(std::string_view line) {
  while (!line.empty() && is_space(line.front())) line.remove_prefix(1);
  while (!line.empty() && is_space(line.back())) line.remove_suffix(1);
  return line;
}

// `s` with control characters and bytes that are not well-formed UTF-8 replaced by '?': names
// taken from a file end up in JSON (header, metadata), which must be valid UTF-8.
inline std::string clean_name(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t len = c < 0x80         ? 1
                      : (c >> 5) == 6  ? 2
                      : (c >> 4) == 14 ? 3
                      : (c >> 3) == 30 ? 4
                                       : 0;
    bool ok = len > 0 && i + len <= s.size() && !(c < 0x20 || c == 0x7f);
    for (std::size_t k = 1; ok && k < len; ++k)
      ok = (static_cast<unsigned char>(s[i + k]) >> 6) == 2;
    if (ok && len > 1) {
      // Reject overlong forms, surrogates and code points above U+10FFFF.
      uint32_t cp = c & (0x7f >> len);
      for (std::size_t k = 1; k < len; ++k)
        cp = cp << 6 | (static_cast<unsigned char>(s[i + k]) & 0x3f);
      static constexpr uint32_t kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
      ok = cp >= kMin[len] && cp <= 0x10ffff && !(cp >= 0xd800 && cp <= 0xdfff);
    }
    if (ok) {
      out.append(s.substr(i, len));
      i += len;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

// Shortest decimal that reads back to exactly `v`.
inline void append_shortest(std::string& s, double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}
inline void append_shortest(std::string& s, float v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, r.ptr);
}

// A file coordinate origin + local: the shortest fixed decimal d such that a reader computing
// float(d - origin) gets `local` back (readers subtract the same origin, chosen from the first
// point). With a zero origin this is the shortest float text.
inline void append_coordinate(std::string& s, double origin, float local) {
  if (origin == 0) return append_shortest(s, local);
  const double v = origin + static_cast<double>(local);
  char buf[64];
  for (int decimals = 0; decimals <= 12; ++decimals) {
    auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
    if (r.ec != std::errc()) break;
    double back = 0;
    std::from_chars(buf, r.ptr, back);
    if (static_cast<float>(back - origin) == local) {
      s.append(buf, r.ptr);
      return;
    }
  }
  append_shortest(s, v);
}

}  // namespace splatkit::text
