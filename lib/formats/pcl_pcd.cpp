#include "formats/pcl_pcd.h"

#include "splatkit/error.h"
#include "splatkit/load_module.h"

namespace splatkit {

const PclPcd& pcl_pcd(const std::string& path) {
  std::string why;
  const PclPcd* module =
      loaded_module<PclPcd>(SPLATKIT_PCL_PCD_MODULE_NAME, SPLATKIT_PCL_PCD_MODULE_BUILD_PATH,
                            kPclPcdEntry, kPclPcdVersion, why);
  if (module == nullptr) throw_unsupported(path, "PCD files need splatkit's PCL module: " + why);
  return *module;
}

}  // namespace splatkit
