#include "formats/xyz.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "formats/text_numbers.h"
#include "splatkit/error.h"
#include "splatkit/position_builder.h"

namespace splatkit {

namespace {

enum class Role { kX, kY, kZ, kNx, kNy, kNz, kR, kG, kB, kRadius, kSkip, kExtra };

struct Column {
  Role role = Role::kSkip;
  std::string name;
  std::size_t extra = 0;  // index into cloud.extras when role == kExtra
};

std::string lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return r;
}

Role role_for(std::string_view name) {
  const std::string n = lower(name);
  if (n == "x") return Role::kX;
  if (n == "y") return Role::kY;
  if (n == "z") return Role::kZ;
  if (n == "nx" || n == "normal_x") return Role::kNx;
  if (n == "ny" || n == "normal_y") return Role::kNy;
  if (n == "nz" || n == "normal_z") return Role::kNz;
  if (n == "r" || n == "red") return Role::kR;
  if (n == "g" || n == "green") return Role::kG;
  if (n == "b" || n == "blue") return Role::kB;
  if (n == "radius") return Role::kRadius;
  if (n == "_") return Role::kSkip;
  return Role::kExtra;
}

// A header token is a name when it is not a number (CloudCompare writes "//X", "Scalar field").
bool looks_like_names(const std::vector<std::string_view>& toks) {
  double v;
  for (auto t : toks)
    if (!t.empty() && !text::parse_double(t, v)) return true;
  return false;
}

bool has_xyz_names(const std::vector<std::string_view>& toks) {
  int found = 0;
  for (auto t : toks) {
    Role r = role_for(t);
    found |= r == Role::kX ? 1 : r == Role::kY ? 2 : r == Role::kZ ? 4 : 0;
  }
  return found == 7;
}

char separator_of(std::string_view line) {
  if (line.find(',') != std::string_view::npos) return ',';
  if (line.find(';') != std::string_view::npos) return ';';
  return 0;
}

const char* separator_name(char sep) { return sep == ',' ? "," : sep == ';' ? ";" : "whitespace"; }

class XyzReader {
 public:
  XyzReader(InputStream& in, const ReadOptions& options)
      : in_(in), options_(options), positions_(doc_.cloud, in.path()) {}
  LoadedCloud read();

 private:
  bool next_content_line(std::string_view& content);
  [[noreturn]] void fail_line(const std::string& what) const;
  void set_columns(const std::vector<std::string_view>& names, const std::string& source);
  void set_columns_by_count(const std::vector<std::string_view>& first_data);
  void add_point(const std::vector<std::string_view>& toks);
  double number(std::string_view tok, std::size_t col) const;
  void check_float(double v, std::string_view tok, std::size_t col, const char* what) const;

  InputStream& in_;
  const ReadOptions& options_;
  LoadedCloud doc_;
  PositionBuilder positions_;
  std::string line_;
  uint64_t line_no_ = 0;
  std::string last_comment_;  // the comment just before the first data line (our own header)
  std::vector<Column> columns_;
  char sep_ = 0;
  bool has_normals_ = false, has_colors_ = false, has_radius_ = false;
};

void XyzReader::fail_line(const std::string& what) const {
  throw_bad_input(in_.path(), "line " + std::to_string(line_no_) + ": " + what);
}

// Next line that is neither blank nor a '#' comment; remembers the last comment seen.
bool XyzReader::next_content_line(std::string_view& content) {
  while (in_.read_line(line_)) {
    ++line_no_;
    std::string_view t = text::trim(line_);
    if (t.empty()) continue;
    if (t.front() == '#') {
      last_comment_.assign(t.substr(1));
      continue;
    }
    content = t;
    return true;
  }
  return false;
}

constexpr const char* kColumnsOption = "the --columns option";

void XyzReader::set_columns(const std::vector<std::string_view>& names, const std::string& source) {
  // The command line's columns are the user's mistake (usage), a header line's the file's.
  const bool option = source == kColumnsOption;
  auto fail = [&](const std::string& what) {
    if (option) throw_usage(what + " in " + source);
    throw_bad_input(in_.path(), what + " in " + source);
  };
  if (names.size() > kMaxAttributes)
    fail(std::to_string(names.size()) + " columns, more than the " +
         std::to_string(kMaxAttributes) + " splatkit reads");
  columns_.clear();
  columns_.reserve(names.size());
  int count[12] = {};
  std::unordered_set<std::string> extra_names;  // duplicate check in constant time per column
  for (auto n : names) {
    if (n.empty()) fail("empty column name");
    Column c;
    c.role = role_for(n);
    c.name = text::clean_name(n);
    if (c.role == Role::kExtra) {
      if (!extra_names.insert(c.name).second) fail("column '" + c.name + "' named twice");
      c.extra = doc_.cloud.extras.size();
      doc_.cloud.extras.push_back({c.name, ScalarType::kFloat64});
    } else if (c.role != Role::kSkip && ++count[static_cast<int>(c.role)] > 1) {
      fail("column '" + c.name + "' named twice");
    }
    columns_.push_back(std::move(c));
  }
  auto n = [&](Role r) { return count[static_cast<int>(r)]; };
  if (!n(Role::kX) || !n(Role::kY) || !n(Role::kZ)) fail("no x, y and z columns");
  has_normals_ = n(Role::kNx) + n(Role::kNy) + n(Role::kNz) > 0;
  if (has_normals_ && !(n(Role::kNx) && n(Role::kNy) && n(Role::kNz)))
    fail("incomplete normal (need nx, ny and nz)");
  has_colors_ = n(Role::kR) + n(Role::kG) + n(Role::kB) > 0;
  if (has_colors_ && !(n(Role::kR) && n(Role::kG) && n(Role::kB)))
    fail("incomplete colour (need r, g and b)");
  has_radius_ = n(Role::kRadius) > 0;
}

// No names: 3 xyz, 4 xyz+intensity, 6 xyz+normal or xyz+rgb, 7 xyz+intensity+rgb,
// 9 xyz+normal+rgb; any other count keeps columns 4.. as extras "column_<k>".
void XyzReader::set_columns_by_count(const std::vector<std::string_view>& first) {
  const std::size_t n = first.size();
  std::vector<std::string> names;
  if (n < 3) fail_line("expected at least 3 columns (x y z), found " + std::to_string(n));
  names = {"x", "y", "z"};
  if (n == 4) names.push_back("intensity");
  if (n == 6) {
    // Integers 0-255 that are not a unit axis read as colour; "0 0 1" stays a normal.
    bool rgb = true;
    double sq = 0;
    for (std::size_t i = 3; i < 6; ++i) {
      double v = 0;
      rgb = rgb && text::is_integer_literal(first[i]) && text::parse_double(first[i], v) &&
            v >= 0 && v <= 255;
      sq += v * v;
    }
    if (rgb && sq != 1)
      names.insert(names.end(), {"r", "g", "b"});
    else
      names.insert(names.end(), {"nx", "ny", "nz"});
  }
  if (n == 7) names.insert(names.end(), {"intensity", "r", "g", "b"});
  if (n == 9) names.insert(names.end(), {"nx", "ny", "nz", "r", "g", "b"});
  if (names.size() != n) {
    names.resize(3);
    for (std::size_t k = 4; k <= n; ++k) names.push_back("column_" + std::to_string(k));
  }
  std::vector<std::string_view> views(names.begin(), names.end());
  set_columns(views, "line " + std::to_string(line_no_) + " (columns guessed from their count)");
}

double XyzReader::number(std::string_view tok, std::size_t col) const {
  double v;
  if (!text::parse_double(tok, v))
    fail_line("column " + std::to_string(col + 1) + " (" + columns_[col].name +
              "): not a number: '" + std::string(tok.substr(0, 40)) + "'");
  return v;
}

// Coordinates, normals and radii are stored as float32: a value beyond its range is an error, not
// an infinity.
void XyzReader::check_float(double v, std::string_view tok, std::size_t col,
                            const char* what) const {
  if (!std::isfinite(v))
    fail_line(std::string("NaN or infinite ") + what + " in column " + std::to_string(col + 1));
  if (!fits_float(v))
    fail_line(std::string(what) + " '" + std::string(tok.substr(0, 40)) + "' in column " +
              std::to_string(col + 1) + " (" + columns_[col].name +
              ") is beyond float range (magnitude above 3.4e38)");
}

void XyzReader::add_point(const std::vector<std::string_view>& toks) {
  if (toks.size() != columns_.size())
    fail_line("expected " + std::to_string(columns_.size()) + " columns, found " +
              std::to_string(toks.size()));
  std::array<double, 3> p{}, nrm{};
  std::array<uint16_t, 3> rgb{};
  float radius = 0;
  SplatCloud& c = doc_.cloud;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    const Column& col = columns_[i];
    if (col.role == Role::kSkip) continue;
    const double v = number(toks[i], i);
    switch (col.role) {
      case Role::kX:
      case Role::kY:
      case Role::kZ:
        check_float(v, toks[i], i, "coordinate");
        p[static_cast<int>(col.role) - static_cast<int>(Role::kX)] = v;
        break;
      case Role::kNx:
      case Role::kNy:
      case Role::kNz:
        check_float(v, toks[i], i, "normal");
        nrm[static_cast<int>(col.role) - static_cast<int>(Role::kNx)] = v;
        break;
      case Role::kR:
      case Role::kG:
      case Role::kB:
        if (!(v >= 0 && v <= 255) || v != std::floor(v))
          fail_line("colour value '" + std::string(toks[i].substr(0, 40)) +
                    "' out of range (integers 0-255) in column " + std::to_string(i + 1));
        rgb[static_cast<int>(col.role) - static_cast<int>(Role::kR)] = static_cast<uint16_t>(v);
        break;
      case Role::kRadius:
        if (!(v >= 0) || !std::isfinite(v)) fail_line("radius must be finite and >= 0");
        check_float(v, toks[i], i, "radius");
        radius = static_cast<float>(v);
        break;
      case Role::kExtra:
        c.extras[col.extra].values.push_back(v);
        break;
      case Role::kSkip:
        break;
    }
  }
  positions_.add(p);
  if (has_normals_)
    c.normals.push_back(
        {static_cast<float>(nrm[0]), static_cast<float>(nrm[1]), static_cast<float>(nrm[2])});
  if (has_colors_) c.colors.push_back(rgb);
  if (has_radius_) c.radii.push_back(radius);
}

LoadedCloud XyzReader::read() {
  std::vector<std::string_view> toks;
  std::string_view content;
  std::string header_kind = "none";
  std::vector<std::string> header_names;  // owned copies: the line buffer is reused
  std::string header_source;
  std::optional<uint64_t> pts_count;
  bool have_data = next_content_line(content);

  if (have_data) {
    std::string_view h = content;
    bool cloudcompare = h.substr(0, 2) == "//";
    if (cloudcompare) h.remove_prefix(2);
    text::split(h, separator_of(h), toks);
    uint64_t count = 0;
    if (cloudcompare || looks_like_names(toks)) {
      header_kind = "names";
      header_source = "the header (line " + std::to_string(line_no_) + ")";
      header_names.assign(toks.begin(), toks.end());
      have_data = next_content_line(content);
    } else if (toks.size() == 1 && text::parse_uint64(toks[0], count)) {
      header_kind = "pts_count";
      pts_count = count;
      have_data = next_content_line(content);
    } else if (!last_comment_.empty()) {
      // A comment naming x, y, z and as many columns as the data is a header (ours is one).
      const std::size_t data_columns = toks.size();
      text::split(last_comment_, separator_of(last_comment_), toks);
      if (has_xyz_names(toks) && toks.size() == data_columns) {
        header_kind = "comment";
        header_source = "the header comment";
        header_names.assign(toks.begin(), toks.end());
      }
    }
  }

  if (!options_.columns.empty()) {
    text::split(options_.columns, separator_of(options_.columns), toks);
    set_columns(toks, kColumnsOption);
  } else if (!header_names.empty()) {
    std::vector<std::string_view> views(header_names.begin(), header_names.end());
    set_columns(views, header_source);
  }

  if (have_data) {
    sep_ = separator_of(content);
    text::split(content, sep_, toks);
    if (columns_.empty()) set_columns_by_count(toks);
    do {
      text::split(content, sep_, toks);
      add_point(toks);
    } while (next_content_line(content));
  }
  positions_.finish();

  SplatCloud& c = doc_.cloud;
  if (pts_count && *pts_count != c.size())
    throw_bad_input(in_.path(), "PTS header line says " + std::to_string(*pts_count) +
                                    " points but the file has " + std::to_string(c.size()));
  nlohmann::json names = nlohmann::json::array();
  for (const auto& col : columns_) names.push_back(col.name);
  doc_.header = {{"columns", names}, {"separator", separator_name(sep_)}, {"header", header_kind}};
  if (pts_count) doc_.header["pts_count"] = *pts_count;
  return std::move(doc_);
}

}  // namespace

LoadedCloud read_xyz(InputStream& in, const ReadOptions& options) {
  return XyzReader(in, options).read();
}

namespace {

std::string column_name(const std::string& name) {
  std::string s = name.empty() ? std::string("_unnamed") : name;
  for (char& ch : s)
    if (text::is_space(ch) || ch == ',' || ch == ';' || ch == '#') ch = '_';
  return s;
}

uint16_t to_8bit(uint16_t v, int bits) {
  return bits == 16 ? static_cast<uint16_t>((static_cast<uint32_t>(v) * 255 + 32767) / 65535) : v;
}

}  // namespace

void write_xyz(const SplatCloud& cloud, OutputFile& out, char sep) {
  std::string s = sep == ' ' ? "# x y z" : "x,y,z";
  auto names = [&](std::initializer_list<const char*> list) {
    for (const char* name : list) (s += sep) += name;
  };
  if (cloud.has_normals()) names({"nx", "ny", "nz"});
  if (cloud.has_colors()) names({"r", "g", "b"});
  if (cloud.has_radii()) names({"radius"});
  for (const auto& e : cloud.extras) (s += sep) += column_name(e.name);
  s += '\n';
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3f& p = cloud.positions[i];
    for (int k = 0; k < 3; ++k) {
      if (k) s += sep;
      text::append_coordinate(s, cloud.origin[k], p[k]);
    }
    if (cloud.has_normals())
      for (int k = 0; k < 3; ++k) {
        s += sep;
        text::append_shortest(s, cloud.normals[i][k]);
      }
    if (cloud.has_colors())
      for (int k = 0; k < 3; ++k) {
        s += sep;
        s += std::to_string(to_8bit(cloud.colors[i][k], cloud.color_bits));
      }
    if (cloud.has_radii()) {
      s += sep;
      text::append_shortest(s, cloud.radii[i]);
    }
    for (const auto& e : cloud.extras) {
      s += sep;
      text::append_shortest(s, e.values[i]);
    }
    s += '\n';
    if (s.size() > (1u << 16)) {
      out.write(s);
      s.clear();
    }
  }
  out.write(s);
}

}  // namespace splatkit
