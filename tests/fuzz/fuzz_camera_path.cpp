// libFuzzer target for splat-view's camera path reader (--path): any input must either give
// cameras that make_projection accepts or throw splatkit::Error; anything else (crash, other
// exception, sanitizer report) is a bug.
#include <cstddef>
#include <cstdint>
#include <string>

#include "apps/read_camera_path.h"
#include "splatkit/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    for (const splatkit::render::Camera& c :
         splatkit::apps::read_camera_path(text, "fuzz.json", {0, 0, 1}, 40, 64, 48))
      (void)splatkit::render::make_projection(c);
  } catch (const splatkit::Error&) {
    // Rejected input: the expected outcome for most mutations.
  }
  return 0;
}
