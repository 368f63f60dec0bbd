// The splatkit_pcl_pcd module (formats/pcl_pcd.h): pcl::PCDReader behind a narrow interface, so
// that only a run reading a .pcd file loads PCL's io and the libraries it links.
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <exception>
#include <optional>
#include <string>
#include <utility>

#include "formats/pcl_pcd.h"

namespace splatkit {

namespace {

std::optional<ScalarType> scalar_type(uint8_t type) {
  switch (type) {
    case pcl::PCLPointField::INT8:
      return ScalarType::kInt8;
    case pcl::PCLPointField::UINT8:
      return ScalarType::kUInt8;
    case pcl::PCLPointField::INT16:
      return ScalarType::kInt16;
    case pcl::PCLPointField::UINT16:
      return ScalarType::kUInt16;
    case pcl::PCLPointField::INT32:
      return ScalarType::kInt32;
    case pcl::PCLPointField::UINT32:
      return ScalarType::kUInt32;
    case pcl::PCLPointField::INT64:
      return ScalarType::kInt64;
    case pcl::PCLPointField::UINT64:
      return ScalarType::kUInt64;
    case pcl::PCLPointField::FLOAT32:
      return ScalarType::kFloat32;
    case pcl::PCLPointField::FLOAT64:
      return ScalarType::kFloat64;
    default:
      return std::nullopt;
  }
}

// PCL prints its own errors on stderr; splatkit reports them as one Error instead.
class QuietPcl {
 public:
  QuietPcl() : saved_(pcl::console::getVerbosityLevel()) {
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
  }
  ~QuietPcl() { pcl::console::setVerbosityLevel(saved_); }
  QuietPcl(const QuietPcl&) = delete;
  QuietPcl& operator=(const QuietPcl&) = delete;

 private:
  pcl::console::VERBOSITY_LEVEL saved_;
};

std::string read(const std::string& path, PclRecords& out) {
  try {
    pcl::PCLPointCloud2 pc;
    Eigen::Vector4f origin;
    Eigen::Quaternionf orientation;
    int version = 0;
    int rc = -1;
    {
      QuietPcl quiet;
      rc = pcl::PCDReader().read(path, pc, origin, orientation, version);
    }
    if (rc < 0) return "PCL could not read the file (error " + std::to_string(rc) + ")";
    out.fields.clear();
    for (const pcl::PCLPointField& f : pc.fields)
      out.fields.push_back({f.name, f.offset, f.count, scalar_type(f.datatype)});
    out.width = pc.width;
    out.height = pc.height;
    out.point_step = pc.point_step;
    out.data = std::move(pc.data);
    return "";
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    return std::string("PCL could not read the file: ") + e.what();
  }
}

const PclPcd kModule{kPclPcdVersion, read};

}  // namespace

}  // namespace splatkit

extern "C" __attribute__((visibility("default"))) const splatkit::PclPcd* splatkit_pcl_pcd() {
  return &splatkit::kModule;
}
