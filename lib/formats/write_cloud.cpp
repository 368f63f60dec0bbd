#include "formats/write_cloud.h"

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
      write_xyz(doc.cloud, out);
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
