#include "terrain/fill_voids.h"

namespace splatkit::terrain {

int64_t fill_row_voids(float* row, int64_t width, bool has_nodata, float nodata) {
  int64_t voids = 0;
  int64_t last_valid = -1;  // index of the last valid sample seen
  int64_t x = 0;
  while (x < width) {
    if (!is_void(row[x], has_nodata, nodata)) {
      last_valid = x++;
      continue;
    }
    int64_t end = x;
    while (end < width && is_void(row[end], has_nodata, nodata)) ++end;
    voids += end - x;
    if (last_valid < 0 && end == width) return width;  // no valid sample in the row
    if (last_valid < 0) {
      for (int64_t i = x; i < end; ++i) row[i] = row[end];
    } else if (end == width) {
      for (int64_t i = x; i < end; ++i) row[i] = row[last_valid];
    } else {
      const double a = row[last_valid], b = row[end];
      const double span = double(end - last_valid);
      for (int64_t i = x; i < end; ++i)
        row[i] = float(a + (b - a) * (double(i - last_valid) / span));
    }
    x = end;
  }
  return voids;
}

}  // namespace splatkit::terrain
