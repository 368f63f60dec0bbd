// write_ply: a SplatCloud as PLY (binary little-endian by default, big-endian or ASCII).
//
// Rows are assembled a block at a time, one column after the other, into a staging buffer that
// goes to the OutputFile; the caller commits. Same cloud and options => the same bytes. Spec:
// ply.md.
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "formats/ply.h"

namespace splatkit {
namespace {

constexpr std::size_t kBlockBytes = 256 * 1024;

// PLY's classic names, understood by every reader; 64-bit integers have none, so they keep the
// sized names (read by splatkit, not by every other reader).
std::string_view ply_type_name(ScalarType t) {
  switch (t) {
    case ScalarType::kInt8:
      return "char";
    case ScalarType::kUInt8:
      return "uchar";
    case ScalarType::kInt16:
      return "short";
    case ScalarType::kUInt16:
      return "ushort";
    case ScalarType::kInt32:
      return "int";
    case ScalarType::kUInt32:
      return "uint";
    case ScalarType::kInt64:
      return "int64";
    case ScalarType::kUInt64:
      return "uint64";
    case ScalarType::kFloat32:
      return "float";
    case ScalarType::kFloat64:
      return "double";
  }
  return "?";
}

enum class Source { kPosition, kNormal, kRadius, kAxis, kMinorRadius, kColor, kExtra };

struct Column {
  std::string name;
  ScalarType type;
  Source source;
  int index = 0;  // axis or colour channel, or extra number
  std::size_t offset = 0;
};

// A header-safe, unique property name: whitespace would split the header line.
std::string unique_name(std::string name, std::set<std::string>& used) {
  for (char& c : name)
    if (static_cast<unsigned char>(c) <= ' ' || c == 127) c = '_';
  if (name.empty()) name = "unnamed";
  std::string candidate = name;
  for (int k = 2; !used.insert(candidate).second; ++k) candidate = name + "_" + std::to_string(k);
  return candidate;
}

std::vector<Column> plan_columns(const SplatCloud& cloud) {
  std::vector<Column> cols;
  std::set<std::string> used;
  auto add = [&](const std::string& name, ScalarType t, Source s, int index) {
    cols.push_back({unique_name(name, used), t, s, index, 0});
  };
  const bool shifted = cloud.origin != std::array<double, 3>{0, 0, 0};
  const ScalarType pos_type = shifted ? ScalarType::kFloat64 : ScalarType::kFloat32;
  for (int a = 0; a < 3; ++a) add(std::string(1, "xyz"[a]), pos_type, Source::kPosition, a);
  if (cloud.has_normals())
    for (int a = 0; a < 3; ++a)
      add(std::string("n") + "xyz"[a], ScalarType::kFloat32, Source::kNormal, a);
  if (cloud.has_radii()) add("radius", ScalarType::kFloat32, Source::kRadius, 0);
  if (cloud.has_ellipses()) {
    for (int a = 0; a < 3; ++a)
      add(std::string("axis_") + "xyz"[a], ScalarType::kFloat32, Source::kAxis, a);
    add("minor_radius", ScalarType::kFloat32, Source::kMinorRadius, 0);
  }
  if (cloud.has_colors()) {
    const ScalarType ct = cloud.color_bits == 16 ? ScalarType::kUInt16 : ScalarType::kUInt8;
    const char* names[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; ++c) add(names[c], ct, Source::kColor, c);
  }
  for (std::size_t i = 0; i < cloud.extras.size(); ++i)
    add(cloud.extras[i].name, cloud.extras[i].type(), Source::kExtra, static_cast<int>(i));
  std::size_t offset = 0;
  for (Column& c : cols) {
    c.offset = offset;
    offset += scalar_size(c.type);
  }
  return cols;
}

// Values n rows from `first` of one column, as double (exact for every source).
void fetch(const SplatCloud& cloud, const Column& c, std::size_t first, std::size_t n,
           double* out) {
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = first + i;
    switch (c.source) {
      case Source::kPosition:
        out[i] = static_cast<double>(cloud.positions[r][c.index]) + cloud.origin[c.index];
        break;
      case Source::kNormal:
        out[i] = cloud.normals[r][c.index];
        break;
      case Source::kRadius:
        out[i] = cloud.radii[r];
        break;
      case Source::kAxis:
        out[i] = cloud.axes[r][c.index];
        break;
      case Source::kMinorRadius:
        out[i] = cloud.minor_radii[r];
        break;
      case Source::kColor:
        out[i] = cloud.colors[r][c.index];
        break;
      case Source::kExtra:
        out[i] = cloud.extras[c.index].values[r];
        break;
    }
  }
}

// Rounds and clamps to T (NaN -> 0 for integers).
template <class T>
T to_type(double v) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(v);
  } else {
    if (!(v == v)) return 0;
    constexpr double lo = static_cast<double>(std::numeric_limits<T>::min());
    constexpr double hi = static_cast<double>(std::numeric_limits<T>::max());
    if (v <= lo) return std::numeric_limits<T>::min();
    if (v >= hi) return std::numeric_limits<T>::max();
    return static_cast<T>(std::nearbyint(v));
  }
}

template <class T>
void store(char* p, T v, bool swap) {
  if constexpr (sizeof(T) > 1) {
    if (swap) {
      char b[sizeof(T)];
      std::memcpy(b, &v, sizeof v);
      for (std::size_t k = 0; k < sizeof(T); ++k) p[k] = b[sizeof(T) - 1 - k];
      return;
    }
  }
  std::memcpy(p, &v, sizeof v);
}

template <class T>
void store_column(const double* v, std::size_t n, char* base, std::size_t stride, bool swap) {
  for (std::size_t i = 0; i < n; ++i) store<T>(base + i * stride, to_type<T>(v[i]), swap);
}

void store_values(ScalarType t, const double* v, std::size_t n, char* base, std::size_t stride,
                  bool swap) {
  switch (t) {
    case ScalarType::kInt8:
      store_column<int8_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kUInt8:
      store_column<uint8_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kInt16:
      store_column<int16_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kUInt16:
      store_column<uint16_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kInt32:
      store_column<int32_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kUInt32:
      store_column<uint32_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kInt64:
      store_column<int64_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kUInt64:
      store_column<uint64_t>(v, n, base, stride, swap);
      break;
    case ScalarType::kFloat32:
      store_column<float>(v, n, base, stride, swap);
      break;
    case ScalarType::kFloat64:
      store_column<double>(v, n, base, stride, swap);
      break;
  }
}

// Shortest text that reads back to the same value of type t.
void append_value(std::string& s, ScalarType t, double v) {
  char buf[40];
  std::to_chars_result r{};
  switch (t) {
    case ScalarType::kFloat32:
      r = std::to_chars(buf, buf + sizeof buf, static_cast<float>(v));
      break;
    case ScalarType::kFloat64:
      r = std::to_chars(buf, buf + sizeof buf, v);
      break;
    case ScalarType::kInt8:
      r = std::to_chars(buf, buf + sizeof buf, to_type<int8_t>(v));
      break;
    case ScalarType::kUInt8:
      r = std::to_chars(buf, buf + sizeof buf, to_type<uint8_t>(v));
      break;
    case ScalarType::kInt16:
      r = std::to_chars(buf, buf + sizeof buf, to_type<int16_t>(v));
      break;
    case ScalarType::kUInt16:
      r = std::to_chars(buf, buf + sizeof buf, to_type<uint16_t>(v));
      break;
    case ScalarType::kInt32:
      r = std::to_chars(buf, buf + sizeof buf, to_type<int32_t>(v));
      break;
    case ScalarType::kUInt32:
      r = std::to_chars(buf, buf + sizeof buf, to_type<uint32_t>(v));
      break;
    case ScalarType::kInt64:
      r = std::to_chars(buf, buf + sizeof buf, to_type<int64_t>(v));
      break;
    case ScalarType::kUInt64:
      r = std::to_chars(buf, buf + sizeof buf, to_type<uint64_t>(v));
      break;
  }
  s.append(buf, r.ptr);
}

struct FaceLayout {
  ScalarType count_type = ScalarType::kUInt8, index_type = ScalarType::kInt32;
};

FaceLayout face_layout(const SplatCloud& cloud) {
  FaceLayout f;
  for (std::size_t k = 0; k + 1 < cloud.face_offsets.size(); ++k)
    if (cloud.face_offsets[k + 1] - cloud.face_offsets[k] > 255) f.count_type = ScalarType::kUInt32;
  if (cloud.size() > static_cast<std::size_t>(std::numeric_limits<int32_t>::max()))
    f.index_type = ScalarType::kUInt32;
  return f;
}

std::string header_text(const SplatCloud& cloud, const std::vector<Column>& cols,
                        const FaceLayout& faces, PlyEncoding encoding,
                        const std::vector<std::string>& comments) {
  std::string h = "ply\nformat ";
  h += encoding == PlyEncoding::kAscii             ? "ascii"
       : encoding == PlyEncoding::kBinaryBigEndian ? "binary_big_endian"
                                                   : "binary_little_endian";
  h += " 1.0\n";
  for (std::string c : comments) {
    for (char& ch : c)
      if (ch == '\n' || ch == '\r') ch = ' ';
    h += "comment " + c + "\n";
  }
  h += "element vertex " + std::to_string(cloud.size()) + "\n";
  for (const Column& c : cols)
    h += "property " + std::string(ply_type_name(c.type)) + " " + c.name + "\n";
  if (cloud.face_count() > 0) {
    h += "element face " + std::to_string(cloud.face_count()) + "\n";
    h += "property list " + std::string(ply_type_name(faces.count_type)) + " " +
         std::string(ply_type_name(faces.index_type)) + " vertex_indices\n";
  }
  h += "end_header\n";
  return h;
}

void write_binary_vertices(const SplatCloud& cloud, const std::vector<Column>& cols, bool swap,
                           OutputFile& out) {
  std::size_t row = 0;
  for (const Column& c : cols) row += scalar_size(c.type);
  const std::size_t block = std::max<std::size_t>(1, kBlockBytes / row);
  std::vector<char> buf(block * row);
  std::vector<double> values(block);
  for (std::size_t first = 0; first < cloud.size(); first += block) {
    const std::size_t n = std::min(block, cloud.size() - first);
    for (const Column& c : cols) {
      fetch(cloud, c, first, n, values.data());
      store_values(c.type, values.data(), n, buf.data() + c.offset, row, swap);
    }
    out.write(buf.data(), n * row);
  }
}

void write_binary_faces(const SplatCloud& cloud, const FaceLayout& f, bool swap, OutputFile& out) {
  std::vector<char> buf;
  for (std::size_t k = 0; k < cloud.face_count(); ++k) {
    const uint32_t begin = cloud.face_offsets[k], end = cloud.face_offsets[k + 1];
    const double count = end - begin;
    const std::size_t at = buf.size();
    buf.resize(at + scalar_size(f.count_type) + (end - begin) * scalar_size(f.index_type));
    store_values(f.count_type, &count, 1, buf.data() + at, 0, swap);
    char* p = buf.data() + at + scalar_size(f.count_type);
    for (uint32_t i = begin; i < end; ++i, p += scalar_size(f.index_type)) {
      const double index = cloud.face_indices[i];
      store_values(f.index_type, &index, 1, p, 0, swap);
    }
    if (buf.size() >= kBlockBytes) {
      out.write(buf.data(), buf.size());
      buf.clear();
    }
  }
  if (!buf.empty()) out.write(buf.data(), buf.size());
}

void write_ascii(const SplatCloud& cloud, const std::vector<Column>& cols, const FaceLayout& f,
                 OutputFile& out) {
  std::string text;
  std::vector<double> value(1);
  for (std::size_t r = 0; r < cloud.size(); ++r) {
    for (std::size_t k = 0; k < cols.size(); ++k) {
      if (k > 0) text += ' ';
      fetch(cloud, cols[k], r, 1, value.data());
      append_value(text, cols[k].type, value[0]);
    }
    text += '\n';
    if (text.size() >= kBlockBytes) {
      out.write(text);
      text.clear();
    }
  }
  for (std::size_t k = 0; k < cloud.face_count(); ++k) {
    const uint32_t begin = cloud.face_offsets[k], end = cloud.face_offsets[k + 1];
    append_value(text, f.count_type, end - begin);
    for (uint32_t i = begin; i < end; ++i) {
      text += ' ';
      append_value(text, f.index_type, cloud.face_indices[i]);
    }
    text += '\n';
    if (text.size() >= kBlockBytes) {
      out.write(text);
      text.clear();
    }
  }
  out.write(text);
}

}  // namespace

void write_ply(const SplatCloud& cloud, OutputFile& out, PlyEncoding encoding,
               const std::vector<std::string>& comments) {
  cloud.check_consistent();
  const std::vector<Column> cols = plan_columns(cloud);
  const FaceLayout faces = face_layout(cloud);
  out.write(header_text(cloud, cols, faces, encoding, comments));
  if (encoding == PlyEncoding::kAscii) {
    write_ascii(cloud, cols, faces, out);
    return;
  }
  const bool little = encoding == PlyEncoding::kBinaryLittleEndian;
  const bool swap = little != (std::endian::native == std::endian::little);
  write_binary_vertices(cloud, cols, swap, out);
  write_binary_faces(cloud, faces, swap, out);
}

}  // namespace splatkit
