#include "formats/write_cloud.h"

#include <algorithm>

#include "formats/las_writer.h"
#include "formats/off.h"
#include "formats/ply.h"
#include "formats/splk.h"
#include "formats/xyz.h"
#include "splatkit/error.h"
#include "splatkit/lower_extension.h"

namespace splatkit {

FileFormat format_of_extension(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext == "ply") return FileFormat::kPly;
  if (ext == "xyz" || ext == "txt" || ext == "pts" || ext == "csv") return FileFormat::kXyz;
  if (ext == "off") return FileFormat::kOff;
  if (ext == "las") return FileFormat::kLas;
  if (ext == "laz") return FileFormat::kLaz;
  if (ext == "pcd") return FileFormat::kPcd;
  if (ext == "splk") return FileFormat::kSplk;
  return FileFormat::kUnknown;
}

FileFormat output_format_for(const std::string& path) {
  const FileFormat f = format_of_extension(path);
  return f == FileFormat::kUnknown ? FileFormat::kSplk : f;
}

FileFormat writable_format(const std::string& path, const WriteOptions& options) {
  FileFormat f = options.format == FileFormat::kUnknown ? output_format_for(path) : options.format;
  if (f == FileFormat::kPcd)
    throw_unsupported(path, std::string("writing ") + std::string(format_name(f)) +
                                " is not supported; write .ply, .splk, .xyz, .off, .las or .laz");
  return f;
}

std::vector<std::string> fields_not_written(const LoadedCloud& doc, FileFormat format,
                                            const WriteOptions& options) {
  const SplatCloud& c = doc.cloud;
  std::vector<std::string> lost;
  if (format == FileFormat::kSplk) return lost;
  const bool las = format == FileFormat::kLas || format == FileFormat::kLaz;
  const bool off = format == FileFormat::kOff;
  const int las_format = las ? las_output_format(doc, options.las_format) : 0;
  if (las && c.has_normals()) lost.push_back("normals");
  if ((las || off) && c.has_radii()) lost.push_back("radii");
  if (format != FileFormat::kPly && c.has_ellipses()) lost.push_back("ellipse axes");
  const bool las_rgb = las_format == 2 || las_format == 3 || las_format >= 7;
  if (las && !las_rgb && c.has_colors()) lost.push_back("colours");
  if ((las || format == FileFormat::kXyz) && c.face_count() > 0) lost.push_back("faces");
  if (c.viewpoint) lost.push_back("viewpoint");
  const std::vector<std::string> las_kept =
      las ? las_kept_attributes(las_format) : std::vector<std::string>{};
  for (const ExtraAttribute& e : c.extras) {
    const bool kept =
        las ? std::find(las_kept.begin(), las_kept.end(), e.name) != las_kept.end() : !off;
    if (!kept) lost.push_back("attribute " + e.name);
  }
  for (const RawChunk& r : doc.chunks) {
    std::string type(r.type, 4);
    for (char& ch : type)
      if (ch < 0x20 || ch > 0x7e) ch = '?';  // a hostile file's type, printed
    const std::pair<const char*, const char*> known[] = {{kSplkGraphType, "neighbour graph"},
                                                         {kSplkClassType, "sharp edges"},
                                                         {kSplkClipType, "clip partners"},
                                                         {kSplkSurfaceType, "surface ids"}};
    std::string what = "chunk";
    for (const auto& [t, name] : known)
      if (type == std::string(t, 4)) what = name;
    lost.push_back(what + " (" + type + ")");
  }
  return lost;
}

void write_cloud(const LoadedCloud& doc, const std::string& path, const WriteOptions& options) {
  writable_format(path, options);  // before OutputFile creates anything
  OutputFile out(path);
  write_cloud(doc, out, options);
  out.commit();
}

void write_cloud(const LoadedCloud& doc, OutputFile& out, const WriteOptions& options) {
  const FileFormat f = writable_format(out.path(), options);
  switch (f) {
    case FileFormat::kPly:
      write_ply(doc.cloud, out,
                options.ascii        ? PlyEncoding::kAscii
                : options.big_endian ? PlyEncoding::kBinaryBigEndian
                                     : PlyEncoding::kBinaryLittleEndian);
      break;
    case FileFormat::kXyz:
      write_xyz(doc.cloud, out, lower_extension(out.path()) == "csv" ? ',' : ' ');
      break;
    case FileFormat::kOff:
      write_off(doc.cloud, out);
      break;
    case FileFormat::kLas:
    case FileFormat::kLaz:
      write_las(doc, out, f == FileFormat::kLaz, options.las_format);
      break;
    default:
      write_splk(doc, out);
      break;
  }
}

}  // namespace splatkit
