// read_ply: PLY header parsing and streaming decode of its elements into a SplatCloud.
//
// The binary vertex element (no list properties) is decoded block by block straight from the
// InputStream buffer into the SoA arrays, one column (property) at a time with a per-type loop;
// x y z / nx ny nz stored as three consecutive native float32 are copied as one 12-byte unit.
// Everything else (ASCII, faces, vertex rows with lists) goes through a row-at-a-time path.
// Every count is checked against the bytes left before anything is allocated. Spec: formats/ply.md.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>
#include <type_traits>
#include <unordered_set>

#include "formats/ply.h"
#include "splatkit/error.h"
#include "splatkit/for_each_chunk.h"
#include "splatkit/position_builder.h"
#include "splatkit/sized_in_parallel.h"

namespace splatkit {
namespace {

enum class Encoding { kAscii, kLittle, kBig };

constexpr std::size_t kMaxHeaderLine = 64 * 1024;
constexpr std::size_t kBlockBytes = 256 * 1024;  // decode block: stays in L2 while columns run
constexpr std::size_t kSampleBytes =
    64 * kOriginSampleSize * 1024;  // origin sample rows: 64 KiB each

struct Property {
  std::string name;
  ScalarType type = ScalarType::kFloat32;  // value type, or the item type of a list
  bool is_list = false;
  ScalarType count_type = ScalarType::kUInt8;
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> properties;

  bool has_lists() const {
    for (const Property& p : properties)
      if (p.is_list) return true;
    return false;
  }
  // Bytes of one binary row, a list counting as its count only (the least a row can take).
  uint64_t min_row_bytes() const {
    uint64_t n = 0;
    for (const Property& p : properties) n += scalar_size(p.is_list ? p.count_type : p.type);
    return n;
  }
  int find(std::string_view wanted) const {
    for (std::size_t i = 0; i < properties.size(); ++i)
      if (properties[i].name == wanted) return static_cast<int>(i);
    return -1;
  }
};

struct Header {
  Encoding encoding = Encoding::kAscii;
  std::vector<Element> elements;
  std::vector<std::string> comments, obj_info;
  uint64_t lines = 0;  // header lines read, so that ASCII data lines are numbered on from there
};

std::string_view encoding_name(Encoding e) {
  switch (e) {
    case Encoding::kAscii:
      return "ascii";
    case Encoding::kLittle:
      return "binary_little_endian";
    case Encoding::kBig:
      return "binary_big_endian";
  }
  return "?";
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> split(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    std::size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

// The text after the keyword, one separating space removed ("comment  a" keeps " a").
std::string rest_after(std::string_view line, std::string_view keyword) {
  std::string_view r = line.substr(keyword.size());
  if (!r.empty() && is_space(r.front())) r.remove_prefix(1);
  return std::string(r);
}

std::string quote_text(std::string_view s) {
  constexpr std::size_t kMax = 40;
  std::string out = "'" + std::string(s.substr(0, kMax));
  if (s.size() > kMax) out += "...";
  return out + "'";
}

// ---------------------------------------------------------------------------------------------
// Header

class HeaderParser {
 public:
  explicit HeaderParser(InputStream& in) : in_(in) {}

  Header parse() {
    if (in_.peek(3) != "ply") throw_bad_input(in_.path(), "missing 'ply' magic (not a PLY file)");
    std::string line;
    next_line(line);
    if (const auto t = split(line); t.size() != 1 || t[0] != "ply")
      fail("missing 'ply' magic: first line is " + quote_text(line));
    while (next_line(line)) {
      std::vector<std::string_view> t = split(line);
      if (t.empty()) continue;
      if (t[0] == "comment") {
        h_.comments.push_back(rest_after(line, "comment"));
      } else if (t[0] == "obj_info") {
        h_.obj_info.push_back(rest_after(line, "obj_info"));
      } else if (t[0] == "format") {
        parse_format(t);
      } else if (t[0] == "element") {
        parse_element(t);
      } else if (t[0] == "property") {
        parse_property(t);
      } else if (t[0] == "end_header") {
        if (t.size() != 1) fail("bad end_header line " + quote_text(line));
        if (!have_format_) fail("end_header before the format line (bad format line)");
        return std::move(h_);
      } else {
        fail(quote_text(line) + " is not a header keyword (missing end_header?)");
      }
    }
    throw_bad_input(in_.path(), "truncated header: end of file after line " +
                                    std::to_string(h_.lines) + " without end_header");
  }

 private:
  bool next_line(std::string& line) {
    if (!in_.read_line(line, kMaxHeaderLine)) return false;
    ++h_.lines;
    return true;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw_bad_input(in_.path(), "line " + std::to_string(h_.lines) + ": " + what);
  }

  void parse_format(const std::vector<std::string_view>& t) {
    const std::string expected =
        " (expected 'format ascii|binary_little_endian|binary_big_endian 1.0')";
    if (have_format_) fail("bad format line: a second format line" + expected);
    if (!h_.elements.empty()) fail("bad format line: it comes after an element" + expected);
    if (t.size() != 3) fail("bad format line" + expected);
    if (t[1] == "ascii")
      h_.encoding = Encoding::kAscii;
    else if (t[1] == "binary_little_endian")
      h_.encoding = Encoding::kLittle;
    else if (t[1] == "binary_big_endian")
      h_.encoding = Encoding::kBig;
    else
      fail("bad format line: unknown encoding " + quote_text(t[1]) + expected);
    double version = 0;
    auto [end, ec] = std::from_chars(t[2].data(), t[2].data() + t[2].size(), version);
    if (ec != std::errc() || end != t[2].data() + t[2].size() || version != 1.0)
      fail("unknown PLY version " + quote_text(t[2]) + " (only 1.0 exists)");
    have_format_ = true;
  }

  void parse_element(const std::vector<std::string_view>& t) {
    if (!have_format_) fail("element before the format line (bad format line)");
    if (t.size() != 3) fail("bad element line (expected 'element <name> <count>')");
    if (h_.elements.size() == kMaxAttributes)
      fail("more than " + std::to_string(kMaxAttributes) +
           " elements (the most splatkit reads; real files have a few)");
    if (!element_names_.insert(std::string(t[1])).second)
      fail("duplicate element " + quote_text(t[1]));
    property_names_.clear();
    Element e;
    e.name = std::string(t[1]);
    e.count = parse_count(e.name, t[2]);
    h_.elements.push_back(std::move(e));
  }

  uint64_t parse_count(const std::string& element, std::string_view s) const {
    const std::string where = "element '" + element + "': count " + quote_text(s);
    if (!s.empty() && s[0] == '-') fail(where + " is negative (bad count)");
    uint64_t v = 0;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec == std::errc::result_out_of_range) fail(where + " overflows 64 bits (bad count)");
    if (ec != std::errc() || end != s.data() + s.size())
      fail(where + " is not a number (bad count)");
    return v;
  }

  ScalarType parse_type(std::string_view s) const {
    std::optional<ScalarType> t = parse_scalar_name(s);
    if (!t) fail("unknown type " + quote_text(s));
    return *t;
  }

  void parse_property(const std::vector<std::string_view>& t) {
    if (h_.elements.empty()) fail("property before any element");
    Element& e = h_.elements.back();
    if (e.properties.size() == kMaxAttributes)
      fail("more than " + std::to_string(kMaxAttributes) + " properties in element '" + e.name +
           "' (the most splatkit reads; real files have tens)");
    Property p;
    if (t.size() >= 2 && t[1] == "list") {
      if (t.size() != 5)
        fail("bad property line (expected 'property list <count type> <type> <name>')");
      p.is_list = true;
      p.count_type = parse_type(t[2]);
      p.type = parse_type(t[3]);
      if (is_floating(p.count_type)) fail("list count type must be an integer type");
      p.name = std::string(t[4]);
    } else {
      if (t.size() != 3) fail("bad property line (expected 'property <type> <name>')");
      p.type = parse_type(t[1]);
      p.name = std::string(t[2]);
    }
    if (!property_names_.insert(p.name).second)
      fail("duplicate property " + quote_text(p.name) + " in element '" + e.name + "'");
    e.properties.push_back(std::move(p));
  }

  InputStream& in_;
  Header h_;
  bool have_format_ = false;
  // Names seen so far (all elements; the current element's properties): duplicate checks in
  // constant time, so that a header of many elements or properties parses in linear time.
  std::unordered_set<std::string> element_names_, property_names_;
};

nlohmann::json header_json(const Header& h) {
  nlohmann::json j = nlohmann::json::object();
  j["encoding"] = std::string(encoding_name(h.encoding));
  j["version"] = "1.0";
  j["elements"] = nlohmann::json::array();
  for (const Element& e : h.elements) {
    nlohmann::json props = nlohmann::json::array();
    for (const Property& p : e.properties) {
      if (p.is_list)
        props.push_back({{"name", p.name},
                         {"type", "list"},
                         {"count_type", std::string(scalar_name(p.count_type))},
                         {"item_type", std::string(scalar_name(p.type))}});
      else
        props.push_back({{"name", p.name}, {"type", std::string(scalar_name(p.type))}});
    }
    j["elements"].push_back({{"name", e.name}, {"count", e.count}, {"properties", props}});
  }
  j["comments"] = h.comments;
  j["obj_info"] = h.obj_info;
  return j;
}

// ---------------------------------------------------------------------------------------------
// Scalar loads

template <class T>
T byte_swapped(T v) {
  if constexpr (sizeof(T) == 1) {
    return v;
  } else {
    using U = std::conditional_t<sizeof(T) == 2, uint16_t,
                                 std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>;
    U u;
    std::memcpy(&u, &v, sizeof u);
    if constexpr (sizeof(T) == 2)
      u = __builtin_bswap16(u);
    else if constexpr (sizeof(T) == 4)
      u = __builtin_bswap32(u);
    else
      u = __builtin_bswap64(u);
    std::memcpy(&v, &u, sizeof v);
    return v;
  }
}

template <class T, bool Swap>
inline T load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (Swap) v = byte_swapped(v);
  return v;
}

template <class T, bool Swap, class Fn>
void visit_typed(const char* base, std::size_t stride, std::size_t n, Fn& fn) {
  for (std::size_t i = 0; i < n; ++i) fn(i, load<T, Swap>(base + i * stride));
}

// Calls fn(i, value) for the n values of type t found at base + i * stride.
template <bool Swap, class Fn>
void visit_column(ScalarType t, const char* base, std::size_t stride, std::size_t n, Fn&& fn) {
  switch (t) {
    case ScalarType::kInt8:
      visit_typed<int8_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kUInt8:
      visit_typed<uint8_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kInt16:
      visit_typed<int16_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kUInt16:
      visit_typed<uint16_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kInt32:
      visit_typed<int32_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kUInt32:
      visit_typed<uint32_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kInt64:
      visit_typed<int64_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kUInt64:
      visit_typed<uint64_t, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kFloat32:
      visit_typed<float, Swap>(base, stride, n, fn);
      break;
    case ScalarType::kFloat64:
      visit_typed<double, Swap>(base, stride, n, fn);
      break;
  }
}

template <class Fn>
void visit_column(bool swap, ScalarType t, const char* base, std::size_t stride, std::size_t n,
                  Fn&& fn) {
  if (swap)
    visit_column<true>(t, base, stride, n, fn);
  else
    visit_column<false>(t, base, stride, n, fn);
}

double load_double(bool swap, ScalarType t, const char* p) {
  double v = 0;
  visit_column(swap, t, p, 0, 1, [&](std::size_t, auto x) { v = static_cast<double>(x); });
  return v;
}

// ---------------------------------------------------------------------------------------------
// Where each vertex property goes

enum class Role : uint8_t {
  kX,
  kY,
  kZ,
  kNx,
  kNy,
  kNz,
  kRadius,
  kRed,
  kGreen,
  kBlue,
  kExtra,
  kSkip
};

struct Slot {
  Role role = Role::kSkip;
  ScalarType type = ScalarType::kFloat32;
  std::size_t offset = 0;  // binary offset in the row (fixed-size rows only)
  std::size_t extra = 0;   // index into cloud.extras for kExtra
  uint16_t color_max = 255, color_scale = 1;
};

// True for types whose values need float64 precision to keep georeferenced coordinates.
bool is_wide(ScalarType t) {
  return t == ScalarType::kFloat64 || t == ScalarType::kInt32 || t == ScalarType::kUInt32 ||
         t == ScalarType::kInt64 || t == ScalarType::kUInt64;
}

struct VertexPlan {
  std::vector<Slot> slots;  // one per property of the vertex element
  bool has_normals = false, has_radii = false, has_colors = false;
  bool wide = false;  // x y z need an origin
  int xyz[3] = {-1, -1, -1}, nxyz[3] = {-1, -1, -1};
};

// Integer channels are clamped to their depth; float channels map 0..1 to 0..255.
uint16_t color_value(double d, bool from_float, const Slot& s) {
  if (from_float)
    d = std::floor(std::clamp(d, 0.0, 1.0) * 255 + 0.5);
  else
    d = std::clamp(d, 0.0, static_cast<double>(s.color_max));
  if (!(d >= 0)) d = 0;  // NaN
  return static_cast<uint16_t>(static_cast<uint16_t>(d) * s.color_scale);
}

// Integers as integers, other values in shortest form (for messages).
std::string number_text(double v) {
  char buf[32];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : std::string("?");
}

int color_depth(ScalarType t) { return is_floating(t) || scalar_size(t) == 1 ? 8 : 16; }

// Finds x y z, nx ny nz, radius and an rgb triple; every other scalar property becomes an extra.
VertexPlan plan_vertex(const InputStream& in, const Element& e, SplatCloud& cloud) {
  VertexPlan plan;
  plan.slots.resize(e.properties.size());
  auto scalar = [&](std::string_view name) {
    int i = e.find(name);
    return i >= 0 && !e.properties[i].is_list ? i : -1;
  };
  auto assign = [&](int i, Role r) { plan.slots[i].role = r; };
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    plan.xyz[a] = scalar(axes[a]);
    if (plan.xyz[a] < 0)
      throw_bad_input(in.path(), std::string("element 'vertex' is missing property '") + axes[a] +
                                     "' (or it is a list)");
    assign(plan.xyz[a], static_cast<Role>(a));
    plan.wide = plan.wide || is_wide(e.properties[plan.xyz[a]].type);
  }
  int n[3] = {scalar("nx"), scalar("ny"), scalar("nz")};
  if (n[0] >= 0 && n[1] >= 0 && n[2] >= 0) {
    plan.has_normals = true;
    for (int a = 0; a < 3; ++a) {
      plan.nxyz[a] = n[a];
      assign(n[a], static_cast<Role>(static_cast<int>(Role::kNx) + a));
    }
  }
  if (int r = scalar("radius"); r >= 0) {
    plan.has_radii = true;
    assign(r, Role::kRadius);
  }
  int c[3] = {scalar("red"), scalar("green"), scalar("blue")};
  if (c[0] < 0 || c[1] < 0 || c[2] < 0)
    c[0] = scalar("diffuse_red"), c[1] = scalar("diffuse_green"), c[2] = scalar("diffuse_blue");
  if (c[0] >= 0 && c[1] >= 0 && c[2] >= 0) {
    plan.has_colors = true;
    int bits = 8;
    for (int i : c) bits = std::max(bits, color_depth(e.properties[i].type));
    cloud.color_bits = bits;
    for (int a = 0; a < 3; ++a) {
      Slot& s = plan.slots[c[a]];
      s.role = static_cast<Role>(static_cast<int>(Role::kRed) + a);
      const int depth = color_depth(e.properties[c[a]].type);
      s.color_max = depth == 8 ? 255 : 65535;
      s.color_scale = depth == 8 && bits == 16 ? 257 : 1;
    }
  }
  std::size_t offset = 0;
  for (std::size_t i = 0; i < e.properties.size(); ++i) {
    const Property& p = e.properties[i];
    Slot& s = plan.slots[i];
    s.type = p.type;
    s.offset = offset;
    offset += scalar_size(p.type);
    if (s.role == Role::kSkip && !p.is_list) {
      s.role = Role::kExtra;
      s.extra = cloud.extras.size();
      cloud.extras.push_back({p.name, p.type});
    }
  }
  return plan;
}

// ---------------------------------------------------------------------------------------------
// Row sources: one row at a time, for ASCII and for binary rows holding lists.

// Context for messages: which element and row is being read.
struct RowPlace {
  const Element* element = nullptr;
  uint64_t row = 0;
  std::string text() const {
    return "element '" + element->name + "' row " + std::to_string(row) + ": ";
  }
};

class BinaryRows {
 public:
  BinaryRows(InputStream& in, bool swap) : in_(in), swap_(swap) {}

  bool begin_row(const RowPlace& place) {
    if (place.element != place_.element)
      truncated_ = "element '" + place.element->name + "' (truncated data)";
    place_ = place;
    return true;
  }
  double scalar(ScalarType t) {
    const char* p = in_.take(scalar_size(t), truncated_.c_str()).data();
    return load_double(swap_, t, p);
  }
  uint64_t list_count(const Property& p) {
    const double c = scalar(p.count_type);
    if (c < 0) fail("list count " + number_text(c) + " is negative");
    // 2^62 keeps n * item size inside 64 bits even when the file size is unknown.
    if (c >= 0x1p62) fail("list count too big: " + number_text(c));
    const uint64_t n = static_cast<uint64_t>(c);
    const std::optional<uint64_t> left = in_.remaining();
    if (left && n > *left / scalar_size(p.type))
      fail("list count too big: " + std::to_string(n) + " items of " +
           std::to_string(scalar_size(p.type)) + " bytes but only " + std::to_string(*left) +
           " bytes remain");
    return n;
  }
  void skip_items(const Property& p, uint64_t n) {
    in_.skip(n * scalar_size(p.type), truncated_.c_str());
  }
  void end_row() {}
  [[noreturn]] void fail(const std::string& what) const { in_.fail(place_.text() + what); }

 private:
  InputStream& in_;
  bool swap_;
  RowPlace place_;
  std::string truncated_;  // context for end-of-file messages, per element
};

template <class T>
bool parse_number(std::string_view s, T& v) {
  if (!s.empty() && s[0] == '+') s.remove_prefix(1);
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && end == s.data() + s.size();
}

class AsciiRows {
 public:
  AsciiRows(InputStream& in, uint64_t header_lines) : in_(in), line_no_(header_lines) {}

  // Reads the row's line (blank lines are skipped); false at end of file.
  bool begin_row(const RowPlace& place) {
    place_ = place;
    do {
      if (!in_.read_line(line_)) return false;
      ++line_no_;
      pos_ = 0;
      skip_spaces();
    } while (pos_ == line_.size());
    return true;
  }
  double scalar(ScalarType t) {
    std::string_view tok = token(t);
    double v = 0;
    bool ok = false;
    switch (t) {
      case ScalarType::kFloat32: {
        float f = 0;
        ok = parse_number(tok, f);
        v = f;
        break;
      }
      case ScalarType::kFloat64:
        ok = parse_number(tok, v);
        break;
      case ScalarType::kInt8:
      case ScalarType::kInt16:
      case ScalarType::kInt32:
      case ScalarType::kInt64:
        ok = parse_integer<int64_t>(tok, t, v);
        break;
      default:
        ok = parse_integer<uint64_t>(tok, t, v);
        break;
    }
    if (!ok) {
      double d = 0;
      if (t == ScalarType::kFloat32 && parse_number(tok, d))
        fail("value " + quote_text(tok) + " is out of range for float (magnitude above 3.4e38 " +
             "or below 1.2e-38)");
      fail("value " + quote_text(tok) + " is not a number of type " + std::string(scalar_name(t)));
    }
    return v;
  }
  uint64_t list_count(const Property& p) {
    std::string_view tok = token(p.count_type);
    int64_t c = 0;
    if (!parse_number(tok, c))
      fail("list count " + quote_text(tok) + " is not a number of type " +
           std::string(scalar_name(p.count_type)));
    if (c < 0) fail("list count " + std::to_string(c) + " is negative");
    if (static_cast<uint64_t>(c) > (line_.size() - pos_ + 1) / 2)
      fail("list count too big: " + std::to_string(c) + " items cannot fit on the line");
    return static_cast<uint64_t>(c);
  }
  void skip_items(const Property& p, uint64_t n) {
    for (uint64_t i = 0; i < n; ++i) scalar(p.type);
  }
  void end_row() {
    skip_spaces();
    if (pos_ != line_.size())
      fail("too many values on the line (" + quote_text(std::string_view(line_).substr(pos_)) +
           " is left over)");
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw_bad_input(in_.path(), "line " + std::to_string(line_no_) + ": " + place_.text() + what);
  }
  uint64_t line() const { return line_no_; }

 private:
  void skip_spaces() {
    while (pos_ < line_.size() && is_space(line_[pos_])) ++pos_;
  }
  std::string_view token(ScalarType t) {
    skip_spaces();
    if (pos_ == line_.size())
      fail("too few values on the line (a " + std::string(scalar_name(t)) + " is missing)");
    std::size_t start = pos_;
    while (pos_ < line_.size() && !is_space(line_[pos_])) ++pos_;
    return std::string_view(line_).substr(start, pos_ - start);
  }
  template <class I>
  bool parse_integer(std::string_view tok, ScalarType t, double& v) const {
    if (std::is_unsigned_v<I> && !tok.empty() && tok[0] == '-' && tok.size() > 1)
      fail("value " + quote_text(tok) + " is out of range for " + std::string(scalar_name(t)));
    I i = 0;
    if (!parse_number(tok, i)) return false;
    if (!fits(t, static_cast<double>(i)))
      fail("value " + quote_text(tok) + " is out of range for " + std::string(scalar_name(t)));
    v = static_cast<double>(i);
    return true;
  }
  static bool fits(ScalarType t, double v) {
    switch (t) {
      case ScalarType::kInt8:
        return v >= -128 && v <= 127;
      case ScalarType::kUInt8:
        return v <= 255;
      case ScalarType::kInt16:
        return v >= -32768 && v <= 32767;
      case ScalarType::kUInt16:
        return v <= 65535;
      case ScalarType::kInt32:
        return v >= -2147483648.0 && v <= 2147483647.0;
      case ScalarType::kUInt32:
        return v <= 4294967295.0;
      default:
        return true;
    }
  }

  InputStream& in_;
  uint64_t line_no_;
  std::string line_;
  std::size_t pos_ = 0;
  RowPlace place_;
};

// ---------------------------------------------------------------------------------------------
// The decoder

class PlyDecoder {
 public:
  PlyDecoder(InputStream& in, Header header) : in_(in), h_(std::move(header)) {
    swap_ = h_.encoding != Encoding::kAscii &&
            (h_.encoding == Encoding::kLittle) != (std::endian::native == std::endian::little);
    for (const Element& e : h_.elements)
      if (e.name == "vertex") vertex_count_ = e.count, has_vertex_ = true;
  }

  SplatCloud run() {
    if (!has_vertex_) throw_bad_input(in_.path(), "no 'vertex' element (missing x/y/z)");
    check_counts_against_file();
    if (h_.encoding == Encoding::kAscii) {
      AsciiRows rows(in_, h_.lines);
      read_elements(rows);
      check_ascii_tail(rows);
    } else {
      BinaryRows rows(in_, swap_);
      read_elements(rows);
      if (!in_.at_eof()) {
        const std::optional<uint64_t> left = in_.remaining();
        in_.fail("trailing garbage after the last element" +
                 (left ? " (" + std::to_string(*left) + " bytes)" : std::string()));
      }
    }
    take_ellipses(cloud_);
    return std::move(cloud_);
  }

 private:
  // Elliptic splats: the float properties axis_x, axis_y, axis_z and minor_radius, read as extras,
  // become cloud.axes and cloud.minor_radii when all four are there with normals and radii.
  static void take_ellipses(SplatCloud& c) {
    const char* names[4] = {"axis_x", "axis_y", "axis_z", "minor_radius"};
    std::size_t at[4];
    for (int k = 0; k < 4; ++k) {
      const ExtraAttribute* e = c.find_extra(names[k]);
      if (e == nullptr || !c.has_normals() || !c.has_radii()) return;
      at[k] = static_cast<std::size_t>(e - c.extras.data());
    }
    const std::size_t n = c.size();
    c.axes.resize(n);
    c.minor_radii.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      c.axes[i] = {static_cast<float>(c.extras[at[0]].values[i]),
                   static_cast<float>(c.extras[at[1]].values[i]),
                   static_cast<float>(c.extras[at[2]].values[i])};
      c.minor_radii[i] = static_cast<float>(c.extras[at[3]].values[i]);
    }
    std::erase_if(c.extras, [&](const ExtraAttribute& e) {
      return std::find(std::begin(names), std::end(names), e.name) != std::end(names);
    });
  }
  template <class Rows>
  void read_elements(Rows& rows) {
    for (const Element& e : h_.elements) {
      if (e.name == "vertex")
        read_vertices(e, rows);
      else if (e.name == "face" && face_list(e) >= 0)
        read_faces(e, rows);
      else
        skip_element(e, rows);
    }
  }

  // Rejects counts the file cannot hold before anything is allocated: binary rows take at least
  // min_row_bytes, ASCII rows of p values at least 2p - 1 bytes (digits and separators).
  void check_counts_against_file() {
    const std::optional<uint64_t> left = in_.remaining();
    if (!left) return;
    uint64_t need = 0;
    for (const Element& e : h_.elements) {
      const uint64_t row = h_.encoding == Encoding::kAscii
                               ? (e.properties.empty() ? 0 : 2 * e.properties.size() - 1)
                               : e.min_row_bytes();
      uint64_t bytes = 0;
      const bool overflow = __builtin_mul_overflow(e.count, row, &bytes) ||
                            __builtin_add_overflow(need, bytes, &need);
      if (overflow || need > *left)
        throw_bad_input(in_.path(), "element '" + e.name + "': " + std::to_string(e.count) +
                                        " rows need at least " +
                                        (overflow ? std::string("2^64") : std::to_string(need)) +
                                        " bytes but only " + std::to_string(*left) +
                                        " follow the header (counts larger than the file)");
    }
  }

  static int face_list(const Element& e) {
    for (const char* name : {"vertex_indices", "vertex_index"}) {
      int i = e.find(name);
      if (i >= 0 && e.properties[i].is_list && !is_floating(e.properties[i].type)) return i;
    }
    return -1;
  }

  // Rows allocated ahead: every row when the file size vouches for the count, else what the data
  // has shown so far (vectors then grow geometrically).
  std::size_t rows_to_reserve(const Element& e, uint64_t per_row_min) const {
    const std::optional<uint64_t> left = in_.remaining();
    uint64_t cap = left ? *left / std::max<uint64_t>(per_row_min, 1) + 1 : 65536;
    return static_cast<std::size_t>(std::min(e.count, cap));
  }

  // --- vertices ---

  template <class Rows>
  void read_vertices(const Element& e, Rows& rows) {
    plan_ = plan_vertex(in_, e, cloud_);
    if constexpr (std::is_same_v<Rows, BinaryRows>) {
      if (!e.has_lists()) return read_vertex_blocks(e);
    }
    reserve_vertices(rows_to_reserve(e, std::max<uint64_t>(e.min_row_bytes(), 1)));
    std::vector<double> values(e.properties.size());
    PositionBuilder positions(cloud_, in_.path(), plan_.wide);
    for (uint64_t r = 0; r < e.count; ++r) {
      read_row(
          e, r, rows, [&](std::size_t i, double v) { values[i] = v; },
          [](std::size_t, uint64_t) { return false; });
      add_vertex(values, positions, rows);
    }
    positions.finish();
  }

  void reserve_vertices(std::size_t n) {
    cloud_.positions.reserve(n);
    if (plan_.has_normals) cloud_.normals.reserve(n);
    if (plan_.has_radii) cloud_.radii.reserve(n);
    if (plan_.has_colors) cloud_.colors.reserve(n);
    for (ExtraAttribute& x : cloud_.extras) x.values.reserve(n);
  }

  void resize_vertices(std::size_t n) {
    resize_geometric(cloud_.positions, n);
    if (plan_.has_normals) resize_geometric(cloud_.normals, n);
    if (plan_.has_radii) resize_geometric(cloud_.radii, n);
    if (plan_.has_colors) resize_geometric(cloud_.colors, n);
    for (ExtraAttribute& x : cloud_.extras) resize_geometric(x.values, n);
  }

  // Geometric growth: a pipe (unknown size) grows the arrays one block at a time.
  template <class V>
  static void resize_geometric(V& v, std::size_t n) {
    if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
    v.resize(n);
  }

  template <class Rows>
  void add_vertex(const std::vector<double>& v, PositionBuilder& positions, Rows& rows) {
    const std::array<double, 3> p = {v[plan_.xyz[0]], v[plan_.xyz[1]], v[plan_.xyz[2]]};
    for (double x : p) {
      if (!std::isfinite(x)) rows.fail("NaN or infinite coordinate");
      // Positions are float32: a double beyond its range is an error, not an infinity.
      if (!fits_float(x))
        rows.fail("coordinate " + number_text(x) +
                  " is beyond float range (magnitude above 3.4e38)");
    }
    positions.add(p);
    if (plan_.has_normals)
      cloud_.normals.push_back({static_cast<float>(v[plan_.nxyz[0]]),
                                static_cast<float>(v[plan_.nxyz[1]]),
                                static_cast<float>(v[plan_.nxyz[2]])});
    if (plan_.has_colors) cloud_.colors.emplace_back();
    for (std::size_t i = 0; i < plan_.slots.size(); ++i) {
      const Slot& s = plan_.slots[i];
      switch (s.role) {
        case Role::kRadius:
          cloud_.radii.push_back(static_cast<float>(v[i]));
          break;
        case Role::kRed:
        case Role::kGreen:
        case Role::kBlue:
          cloud_.colors.back()[static_cast<int>(s.role) - static_cast<int>(Role::kRed)] =
              color_value(v[i], is_floating(s.type), s);
          break;
        case Role::kExtra:
          cloud_.extras[s.extra].values.push_back(v[i]);
          break;
        default:
          break;
      }
    }
  }

  // Binary rows without lists: whole rows are taken from the stream buffer a block at a time and
  // decoded column by column.
  void read_vertex_blocks(const Element& e) {
    const std::size_t row_bytes = static_cast<std::size_t>(e.min_row_bytes());
    if (e.count == 0) return;
    if (row_bytes == 0) throw_bad_input(in_.path(), "element 'vertex' has no properties");
    const std::size_t block_rows = std::max<std::size_t>(1, kBlockBytes / row_bytes);
    // The first block holds the origin's sample too (rows of up to 64 KiB; wider rows sample
    // fewer points).
    const std::size_t first_rows = std::max(
        block_rows, std::min<std::size_t>(kOriginSampleSize,
                                          std::max<std::size_t>(1, kSampleBytes / row_bytes)));
    const bool size_known = in_.remaining().has_value();
    if (size_known) resize_vertices(static_cast<std::size_t>(e.count));
    std::size_t done = 0;
    while (done < e.count) {
      const std::size_t n = static_cast<std::size_t>(
          std::min<uint64_t>(done == 0 ? first_rows : block_rows, e.count - done));
      const uint64_t block_offset = in_.offset();
      // A stream that ends early (a file's size is checked against the counts up front): where.
      const std::size_t have = in_.peek(n * row_bytes).size();
      if (have < n * row_bytes)
        throw_bad_input(in_.path(), "byte " + std::to_string(block_offset + have) +
                                        ": element 'vertex': truncated data: end of file after " +
                                        std::to_string(done + have / row_bytes) + " of " +
                                        std::to_string(e.count) + " rows");
      const char* data = in_.take(n * row_bytes, "element 'vertex' (truncated data)").data();
      if (!size_known) resize_vertices(done + n);
      if (done == 0 && plan_.wide) cloud_.origin = origin_from_rows(data, row_bytes, n);
      decode_block(data, row_bytes, n, done);
      check_positions(data, done, n, block_offset, row_bytes);
      done += n;
    }
  }

  // choose_origin_from_sample over the first rows whose x y z are finite and within float range
  // (the others are rejected by check_positions).
  std::array<double, 3> origin_from_rows(const char* data, std::size_t row_bytes, std::size_t n) {
    std::vector<std::array<double, 3>> sample;
    for (std::size_t i = 0; i < n && sample.size() < kOriginSampleSize; ++i) {
      std::array<double, 3> p;
      bool ok = true;
      for (int a = 0; a < 3; ++a) {
        const Slot& s = plan_.slots[plan_.xyz[a]];
        p[a] = load_double(swap_, s.type, data + i * row_bytes + s.offset);
        ok = ok && fits_float(p[a]);
      }
      if (ok) sample.push_back(p);
    }
    return choose_origin_from_sample(sample);
  }

  // Three consecutive native float32 fields: copied as a Vec3f.
  bool is_packed_triple(const int idx[3]) const {
    if (swap_ || idx[0] < 0) return false;
    const Slot& s0 = plan_.slots[idx[0]];
    for (int a = 0; a < 3; ++a) {
      const Slot& s = plan_.slots[idx[a]];
      if (s.type != ScalarType::kFloat32 || s.offset != s0.offset + 4 * a) return false;
    }
    return true;
  }

  void decode_block(const char* data, std::size_t stride, std::size_t n, std::size_t first) {
    const bool packed_xyz = is_packed_triple(plan_.xyz) && !plan_.wide;
    const bool packed_n = plan_.has_normals && is_packed_triple(plan_.nxyz);
    if (packed_xyz)
      copy_triples(data + plan_.slots[plan_.xyz[0]].offset, stride, n,
                   cloud_.positions.data() + first);
    if (packed_n)
      copy_triples(data + plan_.slots[plan_.nxyz[0]].offset, stride, n,
                   cloud_.normals.data() + first);
    for (const Slot& s : plan_.slots) {
      const char* col = data + s.offset;
      const int role = static_cast<int>(s.role);
      if (s.role <= Role::kZ) {
        if (!packed_xyz) decode_positions(s, col, stride, n, first);
      } else if (s.role <= Role::kNz) {
        if (packed_n) continue;
        float Vec3f::*m = role == 3 ? &Vec3f::x : role == 4 ? &Vec3f::y : &Vec3f::z;
        Vec3f* dst = cloud_.normals.data() + first;
        visit_column(swap_, s.type, col, stride, n,
                     [&](std::size_t i, auto v) { dst[i].*m = static_cast<float>(v); });
      } else if (s.role == Role::kRadius) {
        float* dst = cloud_.radii.data() + first;
        visit_column(swap_, s.type, col, stride, n,
                     [&](std::size_t i, auto v) { dst[i] = static_cast<float>(v); });
      } else if (s.role <= Role::kBlue) {
        const int c = role - static_cast<int>(Role::kRed);
        auto* dst = cloud_.colors.data() + first;
        visit_column(swap_, s.type, col, stride, n, [&](std::size_t i, auto v) {
          using T = decltype(v);
          if constexpr (std::is_same_v<T, uint8_t> || std::is_same_v<T, uint16_t>)
            dst[i][c] = static_cast<uint16_t>(v * s.color_scale);  // in range by construction
          else
            dst[i][c] = color_value(static_cast<double>(v), std::is_floating_point_v<T>, s);
        });
      } else if (s.role == Role::kExtra) {
        ExtraValues& dst = cloud_.extras[s.extra].values;  // of the property's type
        visit_column(swap_, s.type, col, stride, n, [&](std::size_t i, auto v) {
          dst.as<decltype(v)>()[first + i] = v;
        });
      }
    }
  }

  static void copy_triples(const char* src, std::size_t stride, std::size_t n, Vec3f* dst) {
    static_assert(sizeof(Vec3f) == 12);
    for (std::size_t i = 0; i < n; ++i) std::memcpy(&dst[i], src + i * stride, 12);
  }

  void decode_positions(const Slot& s, const char* col, std::size_t stride, std::size_t n,
                        std::size_t first) {
    const int a = static_cast<int>(s.role);
    float Vec3f::*m = a == 0 ? &Vec3f::x : a == 1 ? &Vec3f::y : &Vec3f::z;
    Vec3f* dst = cloud_.positions.data() + first;
    if (plan_.wide) {
      const double o = cloud_.origin[a];
      visit_column(swap_, s.type, col, stride, n, [&](std::size_t i, auto v) {
        dst[i].*m = static_cast<float>(static_cast<double>(v) - o);
      });
    } else {
      visit_column(swap_, s.type, col, stride, n,
                   [&](std::size_t i, auto v) { dst[i].*m = static_cast<float>(v); });
    }
  }

  // Names the first row whose x, y or z is NaN, infinite or beyond float range (after the
  // origin is subtracted), with the value as stored in the file.
  void check_positions(const char* data, std::size_t first, std::size_t n, uint64_t block_offset,
                       std::size_t row_bytes) const {
    const Vec3f* p = cloud_.positions.data() + first;
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isfinite(p[i].x) && std::isfinite(p[i].y) && std::isfinite(p[i].z)) continue;
      const std::string where = "byte " + std::to_string(block_offset + i * row_bytes) +
                                ": element 'vertex' row " + std::to_string(first + i) + ": ";
      for (int a = 0; a < 3; ++a) {
        const Slot& s = plan_.slots[plan_.xyz[a]];
        const double v = load_double(swap_, s.type, data + i * row_bytes + s.offset);
        if (!std::isfinite(v)) throw_bad_input(in_.path(), where + "NaN or infinite coordinate");
        if (!std::isfinite(static_cast<float>(v - cloud_.origin[a])))
          throw_bad_input(in_.path(), where + "coordinate " + number_text(v) +
                                          " is beyond float range (magnitude above 3.4e38)");
      }
    }
  }

  // --- rows ---

  // Reads one row: on_scalar(property index, value) for scalars, on_list(property index, count)
  // for lists, whose items the callee must consume (items of lists it ignores are skipped here
  // when on_list returns without reading them: see read_faces).
  template <class Rows, class OnScalar, class OnList>
  void read_row(const Element& e, uint64_t r, Rows& rows, OnScalar&& on_scalar, OnList&& on_list) {
    if (!rows.begin_row({&e, r}))
      rows.fail("truncated data: end of file after " + std::to_string(r) + " of " +
                std::to_string(e.count) + " rows");
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      if (!p.is_list) {
        on_scalar(i, rows.scalar(p.type));
        continue;
      }
      const uint64_t n = rows.list_count(p);
      if (!on_list(i, n)) rows.skip_items(p, n);
    }
    rows.end_row();
  }

  template <class Rows>
  void read_faces(const Element& e, Rows& rows) {
    const std::size_t list = static_cast<std::size_t>(face_list(e));
    const ScalarType item = e.properties[list].type;
    cloud_.face_offsets.reserve(rows_to_reserve(e, std::max<uint64_t>(e.min_row_bytes(), 1)) + 1);
    cloud_.face_offsets.push_back(0);
    auto one_row = [&](uint64_t r) {
      read_row(
          e, r, rows, [](std::size_t, double) {},
          [&](std::size_t i, uint64_t n) {
            if (i != list) return false;
            read_face_indices(rows, item, n);
            return true;
          });
      if (cloud_.face_indices.size() > std::numeric_limits<uint32_t>::max())
        rows.fail("more than 2^32 face indices in total");
      cloud_.face_offsets.push_back(static_cast<uint32_t>(cloud_.face_indices.size()));
    };
    uint64_t r = 0;
    if constexpr (std::is_same_v<Rows, BinaryRows>) {
      const ScalarType count = e.properties[list].count_type;
      if (e.properties.size() == 1 && scalar_size(count) == 1 && scalar_size(item) == 4) {
        // Triangles' indices allocated ahead (within what the file holds): growing the vector
        // copied it and faulted in its pages again at each doubling.
        const std::optional<uint64_t> left = in_.remaining();
        if (left) cloud_.face_indices.reserve(std::min(3 * e.count, *left / 4));
        // Their pages (and the row offsets') mapped in parallel: faulted in one by one, they
        // were a quarter of the reading's time.
        for (auto* v : {&cloud_.face_indices, &cloud_.face_offsets})
          map_pages_in_parallel(v->data() + v->size(), v->data() + v->capacity());
        r = read_face_blocks(e, one_row);
      }
    }
    for (; r < e.count; ++r) one_row(r);
  }

  // A block that starts with at least kParallelRows triangle rows (count 3, then three 32-bit
  // indices below `limit`), up to `most` of them: the rows it holds whole are appended to the
  // faces in parallel chunks and their number returned. 0, nothing appended, when a row among
  // them is not such a triangle (read_face_blocks' serial loop then takes the block row by row).
  std::size_t whole_triangles(std::string_view block, uint64_t most, uint64_t limit) {
    constexpr std::size_t kParallelRows = std::size_t{1} << 14, kChunk = std::size_t{1} << 13;
    std::vector<uint32_t>& indices = cloud_.face_indices;
    std::vector<uint32_t>& offsets = cloud_.face_offsets;
    const uint64_t base = indices.size();
    const auto rows = static_cast<std::size_t>(std::min<uint64_t>(
        {block.size() / 13, most, (std::numeric_limits<uint32_t>::max() - base) / 3}));
    if (rows < kParallelRows) return 0;
    const std::size_t first_offset = offsets.size();
    indices.resize(base + 3 * rows);  // within the capacity reserved (and mapped) for them
    offsets.resize(first_offset + rows);
    std::vector<uint8_t> bad(chunk_count(rows, kChunk), 0);
    // The byte order a template argument and the checks folded into one flag: the loop has no
    // branch but its own.
    const auto parse = [&](auto swap, std::size_t b, std::size_t e) {
      const char* q = block.data() + 13 * b;
      uint32_t* out = indices.data() + base + 3 * b;
      uint32_t* end = offsets.data() + first_offset + b;
      bool wrong = false;
      for (std::size_t i = b; i < e; ++i, q += 13, out += 3) {
        uint32_t v[3];
        std::memcpy(v, q + 1, 12);
        if constexpr (decltype(swap)::value)
          for (uint32_t& x : v) x = __builtin_bswap32(x);
        wrong |= (q[0] != 3) | (std::max({v[0], v[1], v[2]}) >= limit);
        std::memcpy(out, v, 12);
        *end++ = static_cast<uint32_t>(base + 3 * (i + 1));
      }
      return wrong;
    };
    for_each_chunk(rows, kChunk, [&](std::size_t c, std::size_t b, std::size_t e) {
      bad[c] = swap_ ? parse(std::true_type{}, b, e) : parse(std::false_type{}, b, e);
    });
    if (std::find(bad.begin(), bad.end(), 1) == bad.end()) return rows;
    indices.resize(base);
    offsets.resize(first_offset);
    return 0;
  }

  // Binary faces whose only property is the index list, of 8-bit counts and 32-bit indices (what
  // mesh writers write): parsed a block at a time, the stream taking each block's whole rows at
  // once (one bounds check and one checksum update per block, not per value; on a 4M-vertex mesh
  // the value-by-value reading was 30 % of build-qsplat's instructions). A row the block does not
  // hold whole, or that breaks a rule, goes through one_row, which reads it or says what is wrong
  // as for any other file. Returns the rows read.
  template <class OneRow>
  uint64_t read_face_blocks(const Element& e, OneRow& one_row) {
    constexpr std::size_t kBlock = std::size_t{1} << 20;
    const Property& p = e.properties[0];
    const bool signed_count = p.count_type == ScalarType::kInt8;
    const bool signed_item = p.type == ScalarType::kInt32;
    const uint64_t limit = std::min<uint64_t>(vertex_count_, uint64_t{1} << 32);
    constexpr uint64_t kMaxIndices = std::numeric_limits<uint32_t>::max();
    std::vector<uint32_t>& indices = cloud_.face_indices;
    // Triangles, nearly every mesh's rows, a run at a time into a small batch appended whole
    // (push_back per value kept the vectors' ends in memory); the loop below takes every other
    // row and every row that breaks a rule.
    constexpr std::size_t kBatch = 1024;
    const uint64_t triangle_limit = signed_item ? std::min<uint64_t>(limit, 0x80000000u) : limit;
    const bool swap = swap_;
    uint32_t batch[3 * kBatch], ends[kBatch];
    uint64_t r = 0;
    while (r < e.count) {
      const std::string_view block = in_.peek(kBlock);
      std::size_t at = 0;
      if (const std::size_t rows = whole_triangles(block, e.count - r, triangle_limit)) {
        at = 13 * rows;
        r += rows;
      }
      while (r < e.count && at < block.size()) {
        const uint64_t base = indices.size();
        const std::size_t most = static_cast<std::size_t>(
            std::min<uint64_t>({kBatch, e.count - r, (kMaxIndices - base) / 3}));
        std::size_t rows = 0;
        for (; rows < most && at + 13 <= block.size() && block[at] == 3; ++rows, at += 13) {
          uint32_t v[3];
          std::memcpy(v, block.data() + at + 1, 12);
          if (swap)
            for (uint32_t& x : v) x = __builtin_bswap32(x);
          if (std::max({v[0], v[1], v[2]}) >= triangle_limit) break;
          std::memcpy(batch + 3 * rows, v, 12);
          ends[rows] = static_cast<uint32_t>(base + 3 * (rows + 1));
        }
        if (rows > 0) {
          indices.insert(indices.end(), batch, batch + 3 * rows);
          cloud_.face_offsets.insert(cloud_.face_offsets.end(), ends, ends + rows);
          r += rows;
          continue;
        }
        const auto c = static_cast<uint8_t>(block[at]);
        const std::size_t need = 1 + 4 * std::size_t{c};
        if ((signed_count && c >= 128) || at + need > block.size() ||
            indices.size() + c > kMaxIndices)
          break;
        const char* q = block.data() + at + 1;
        const std::size_t start = indices.size();
        for (std::size_t k = 0; k < c; ++k) {
          uint32_t v;
          std::memcpy(&v, q + 4 * k, 4);
          if (swap_) v = __builtin_bswap32(v);
          if ((signed_item && v >= 0x80000000u) || v >= limit) break;
          indices.push_back(v);
        }
        if (indices.size() != start + c) {
          indices.resize(start);
          break;
        }
        cloud_.face_offsets.push_back(static_cast<uint32_t>(indices.size()));
        at += need;
        ++r;
      }
      in_.take(at, "faces");
      if (r < e.count) one_row(r++);
    }
    return r;
  }

  template <class Rows>
  void read_face_indices(Rows& rows, ScalarType item, uint64_t n) {
    // Faces index with uint32: vertices past 2^32 cannot be referenced.
    const double limit = static_cast<double>(std::min<uint64_t>(vertex_count_, uint64_t{1} << 32));
    for (uint64_t k = 0; k < n; ++k) {
      const double v = rows.scalar(item);
      if (!(v >= 0 && v < limit))
        rows.fail("vertex index " + number_text(v) + " out of range (" +
                  std::to_string(vertex_count_) + " vertices)");
      cloud_.face_indices.push_back(static_cast<uint32_t>(v));
    }
  }

  template <class Rows>
  void skip_element(const Element& e, Rows& rows) {
    if constexpr (std::is_same_v<Rows, BinaryRows>) {
      if (!e.has_lists()) {
        uint64_t bytes = 0;
        if (__builtin_mul_overflow(e.count, e.min_row_bytes(), &bytes))
          in_.fail("element '" + e.name + "' is larger than 2^64 bytes (bad count)");
        in_.skip(bytes, "skipped element (truncated data)");
        return;
      }
    }
    if (e.properties.empty()) return;
    for (uint64_t r = 0; r < e.count; ++r)
      read_row(
          e, r, rows, [](std::size_t, double) {}, [](std::size_t, uint64_t) { return false; });
  }

  void check_ascii_tail(AsciiRows& rows) {
    std::string line;
    uint64_t line_no = rows.line();
    while (in_.read_line(line)) {
      ++line_no;
      for (char c : line)
        if (!is_space(c))
          throw_bad_input(in_.path(),
                          "line " + std::to_string(line_no) +
                              ": trailing garbage after the last element: " + quote_text(line));
    }
  }

  InputStream& in_;
  Header h_;
  bool swap_ = false;
  bool has_vertex_ = false;
  uint64_t vertex_count_ = 0;
  VertexPlan plan_;
  SplatCloud cloud_;
};

}  // namespace

LoadedCloud read_ply(InputStream& in, const ReadOptions& options) {
  (void)options;
  Header header = HeaderParser(in).parse();
  LoadedCloud doc;
  doc.format = "ply";
  doc.header = header_json(header);
  doc.cloud = PlyDecoder(in, std::move(header)).run();
  return doc;
}

}  // namespace splatkit
