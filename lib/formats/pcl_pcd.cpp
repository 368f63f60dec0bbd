#include "formats/pcl_pcd.h"

#include <mutex>

#include "splatkit/error.h"
#include "splatkit/load_module.h"

namespace splatkit {

namespace {

// Loads the module, or returns why not.
const PclPcd* load(std::string& why) {
  std::string path;
  void* symbol = load_module(SPLATKIT_PCL_PCD_MODULE_NAME, SPLATKIT_PCL_PCD_MODULE_BUILD_PATH,
                             kPclPcdEntry, why, path);
  if (symbol == nullptr) return nullptr;
  using Entry = const PclPcd* (*)();
  const PclPcd* module = reinterpret_cast<Entry>(symbol)();
  if (module == nullptr || module->version != kPclPcdVersion) {
    why = path + " is not this build's module";
    return nullptr;
  }
  return module;
}

}  // namespace

const PclPcd& pcl_pcd(const std::string& path) {
  static std::string why;
  static const PclPcd* module = nullptr;
  static std::once_flag once;
  std::call_once(once, [] { module = load(why); });
  if (module == nullptr) throw_unsupported(path, "PCD files need splatkit's PCL module: " + why);
  return *module;
}

}  // namespace splatkit
