#include "formats/read_cloud.h"

#include <algorithm>
#include <cctype>

#include "formats/las.h"
#include "formats/off.h"
#include "formats/ply.h"
#include "formats/read_qsplat.h"
#include "formats/splk.h"
#include "formats/spt_codes.h"
#include "formats/text_numbers.h"
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

// Detaches the progress callback from the stream however the read ends.
class ProgressAttachment {
 public:
  ProgressAttachment(InputStream& in, const ProgressFn& progress) : in_(in) {
    in_.set_progress(progress, "reading");
  }
  ~ProgressAttachment() { in_.set_progress(nullptr); }
  ProgressAttachment(const ProgressAttachment&) = delete;
  ProgressAttachment& operator=(const ProgressAttachment&) = delete;

 private:
  InputStream& in_;
};

}  // namespace

bool looks_like_text_columns(std::string_view head, bool complete) {
  for (char ch : head) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 && ch != '\n' && !text::is_space(ch)) return false;  // binary
  }
  std::vector<std::string_view> toks;
  bool skipped_header = false;
  while (!head.empty()) {
    const std::size_t nl = head.find('\n');
    const bool cut = nl == std::string_view::npos && !complete;  // the line goes on past `head`
    std::string_view line = text::trim(head.substr(0, nl));
    head.remove_prefix(nl == std::string_view::npos ? head.size() : nl + 1);
    if (line.empty() || line.front() == '#') continue;
    if (line.substr(0, 2) == "//") line.remove_prefix(2);  // CloudCompare's header
    const char sep = line.find(',') != std::string_view::npos   ? ','
                     : line.find(';') != std::string_view::npos ? ';'
                                                                : 0;
    text::split(line, sep, toks);
    if (cut && !toks.empty()) toks.pop_back();  // its last value may be incomplete
    double v = 0;
    bool numbers = true;
    for (std::string_view t : toks) numbers = numbers && text::parse_double(t, v);
    if (numbers && toks.size() >= 3) return true;
    // One header line (names, or a PTS count) may come before the data.
    if (skipped_header || cut) return false;
    skipped_header = true;
  }
  return false;
}

// The magic bytes of TIFF (both byte orders, BigTIFF too), OpenEXR and PNG, or the extension of
// an SRTM tile (.hgt, which has no magic): the heightmaps build-ham reads.
bool looks_like_heightmap(std::string_view head, const std::string& path) {
  using namespace std::string_view_literals;
  for (std::string_view magic :
       {"II*\0"sv, "MM\0*"sv, "II+\0"sv, "MM\0+"sv, "\x76\x2f\x31\x01"sv, "\x89PNG\r\n\x1a\n"sv})
    if (head.substr(0, magic.size()) == magic) return true;
  return lower_extension(path) == "hgt";
}

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

LoadedCloud read_cloud(InputStream& in, const ReadOptions& options, const ProgressFn& progress) {
  constexpr std::size_t kSniffBytes = 4096;
  const std::string_view head = in.peek(kSniffBytes);
  if (head.empty()) throw_bad_input(in.path(), "file is empty (0 bytes)");
  FileFormat f = detect_format(in, in.path());
  if (f == FileFormat::kUnknown) f = options.assume;
  if (f == FileFormat::kUnknown &&
      (!options.columns.empty() || looks_like_text_columns(head, head.size() < kSniffBytes)))
    f = FileFormat::kXyz;
  ProgressAttachment attach(in, progress);
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
      if (doc.header.contains("compressed")) f = FileFormat::kLaz;  // by content, not by name
      break;
    case FileFormat::kSplk:
      doc = read_splk(in, options);
      break;
    case FileFormat::kLaz:
      doc = read_las(in, options);
      break;
    case FileFormat::kPcd:
#ifdef SPLATKIT_WITH_PCL
      doc = read_pcd(in, options);
      break;
#else
      throw_unsupported(in.path(), "PCD support was not built (SPLATKIT_WITH_PCL=OFF)");
#endif
    case FileFormat::kUnknown:
      if (looks_like_qsplat(head) || spt::looks_like_spt(head))
        throw_unsupported(in.path(),
                          std::string("a ") +
                              (looks_like_qsplat(head) ? "QSplat hierarchy (.qs)"
                                                       : "Sequential Point Tree (.spt)") +
                              ", not a point cloud: splat-view renders it and "
                              "splat-info describes it");
      if (looks_like_heightmap(head, in.path()))
        throw_unsupported(in.path(),
                          "a heightmap (TIFF, EXR, PNG or SRTM .hgt), not a point cloud: "
                          "splat-view --terrain renders it, build-ham builds its tiles, "
                          "splat-info describes it");
      throw_unsupported(in.path(),
                        "unknown file format (not PLY, PCD, LAS, OFF, .splk or text columns by "
                        "content; name it .xyz/.pts/.txt/.csv or give --columns for text)");
  }
  doc.format = std::string(format_name(f));
  doc.cloud.check_consistent();
  progress(1.0, "reading");
  return doc;
}

LoadedCloud read_cloud(const std::string& path, const ReadOptions& options,
                       const ProgressFn& progress) {
  InputStream in(path);
  return read_cloud(in, options, progress);
}

}  // namespace splatkit
