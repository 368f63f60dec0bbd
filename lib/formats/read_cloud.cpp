#include "formats/read_cloud.h"

#include <algorithm>
#include <cctype>

#include "formats/las.h"
#include "formats/off.h"
#include "formats/ply.h"
#include "formats/splk.h"
#include "formats/xyz.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"
#ifdef SPLATKIT_WITH_PCL
#include "formats/pcd.h"
#endif

namespace splatkit {

std::string_view format_name(FileFormat f) {
  switch (f) {
    case FileFormat::kPly:
      return "ply";
    case FileFormat::kXyz:
      return "xyz";
    case FileFormat::kPcd:
      return "pcd";
    case FileFormat::kOff:
      return "off";
    case FileFormat::kLas:
      return "las";
    case FileFormat::kLaz:
      return "laz";
    case FileFormat::kSplk:
      return "splk";
    case FileFormat::kUnknown:
      break;
  }
  return "unknown";
}

namespace {

bool starts_with_word(std::string_view s, std::string_view word) {
  if (s.substr(0, word.size()) != word) return false;
  return s.size() == word.size() || std::isspace(static_cast<unsigned char>(s[word.size()]));
}

// The first non-comment line of a PCD header starts with one of these keywords.
bool looks_like_pcd(std::string_view s) {
  while (!s.empty() && s.front() == '#') {
    auto nl = s.find('\n');
    if (nl == std::string_view::npos) return false;
    s.remove_prefix(nl + 1);
  }
  return starts_with_word(s, "VERSION") || starts_with_word(s, "FIELDS");
}

}  // namespace

FileFormat detect_format(InputStream& in, const std::string& path) {
  std::string_view head = in.peek(512);
  const std::string ext = lower_extension(path);
  if (is_splk_magic(head)) return FileFormat::kSplk;
  if (starts_with_word(head, "ply")) return FileFormat::kPly;
  if (head.substr(0, 4) == "LASF") return ext == "laz" ? FileFormat::kLaz : FileFormat::kLas;
  if (head.substr(0, 6) == "# .PCD" || looks_like_pcd(head)) return FileFormat::kPcd;
  for (std::string_view w : {"OFF", "COFF", "NOFF", "CNOFF", "STOFF", "4OFF", "nOFF"})
    if (head.substr(0, w.size()) == w) return FileFormat::kOff;
  if (ext == "ply") return FileFormat::kPly;
  if (ext == "las") return FileFormat::kLas;
  if (ext == "laz") return FileFormat::kLaz;
  if (ext == "pcd") return FileFormat::kPcd;
  if (ext == "off") return FileFormat::kOff;
  if (ext == "splk") return FileFormat::kSplk;
  if (ext == "xyz" || ext == "pts" || ext == "txt" || ext == "csv" || ext == "asc" ||
      ext == "pwn" || ext == "xyzn")
    return FileFormat::kXyz;
  return FileFormat::kUnknown;
}

LoadedCloud read_cloud(InputStream& in, const ReadOptions& options) {
  FileFormat f = detect_format(in, in.path());
  if (f == FileFormat::kUnknown) f = options.assume;
  LoadedCloud doc;
  switch (f) {
    case FileFormat::kPly:
      doc = read_ply(in, options);
      break;
    case FileFormat::kXyz:
      doc = read_xyz(in, options);
      break;
    case FileFormat::kOff:
      doc = read_off(in, options);
      break;
    case FileFormat::kLas:
      doc = read_las(in, options);
      break;
    case FileFormat::kSplk:
      doc = read_splk(in, options);
      break;
    case FileFormat::kLaz:
      throw_unsupported(in.path(),
                        "LAZ (compressed LAS) is not supported; decompress it first, e.g. "
                        "'laszip -i in.laz -o out.las' or 'pdal translate in.laz out.las'");
    case FileFormat::kPcd:
#ifdef SPLATKIT_WITH_PCL
      doc = read_pcd(in, options);
      break;
#else
      throw_unsupported(in.path(), "PCD support was not built (SPLATKIT_WITH_PCL=OFF)");
#endif
    case FileFormat::kUnknown:
      throw_unsupported(in.path(),
                        "unknown file format (not PLY, PCD, LAS, OFF or .splk by content; name it "
                        ".xyz/.pts/.txt/.csv for text columns)");
  }
  doc.format = std::string(format_name(f));
  doc.cloud.check_consistent();
  return doc;
}

LoadedCloud read_cloud(const std::string& path, const ReadOptions& options) {
  InputStream in(path);
  return read_cloud(in, options);
}

}  // namespace splatkit
