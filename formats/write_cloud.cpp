#include "formats/write_cloud.h"

#include "formats/off.h"
#include "formats/ply.h"
#include "formats/splk.h"
#include "formats/xyz.h"
#include "splatkit/error.h"

namespace splatkit {

FileFormat output_format_for(const std::string& path) {
  auto ends_with = [&](const char* ext) {
    std::string e(ext);
    if (path.size() < e.size()) return false;
    for (std::size_t i = 0; i < e.size(); ++i)
      if (std::tolower(static_cast<unsigned char>(path[path.size() - e.size() + i])) != e[i])
        return false;
    return true;
  };
  if (ends_with(".ply")) return FileFormat::kPly;
  if (ends_with(".xyz") || ends_with(".txt") || ends_with(".pts") || ends_with(".csv"))
    return FileFormat::kXyz;
  if (ends_with(".off")) return FileFormat::kOff;
  if (ends_with(".las") || ends_with(".laz")) return FileFormat::kLas;
  if (ends_with(".pcd")) return FileFormat::kPcd;
  return FileFormat::kSplk;
}

void write_cloud(const LoadedCloud& doc, const std::string& path, const WriteOptions& options) {
  FileFormat f = options.format == FileFormat::kUnknown ? output_format_for(path) : options.format;
  if (f == FileFormat::kLas || f == FileFormat::kLaz || f == FileFormat::kPcd)
    throw_unsupported(path, std::string("writing ") + std::string(format_name(f)) +
                                " is not supported; write .ply, .splk, .xyz or .off");
  OutputFile out(path);
  switch (f) {
    case FileFormat::kPly:
      write_ply(doc.cloud, out,
                options.ascii        ? PlyEncoding::kAscii
                : options.big_endian ? PlyEncoding::kBinaryBigEndian
                                     : PlyEncoding::kBinaryLittleEndian);
      break;
    case FileFormat::kXyz: write_xyz(doc.cloud, out); break;
    case FileFormat::kOff: write_off(doc.cloud, out); break;
    default: write_splk(doc, out); break;
  }
  out.commit();
}

}  // namespace splatkit
