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

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

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
