// Per-pixel normal error of a splat-view EXR of the unit sphere at the origin (render-quality.sh):
//   bench_render_quality IMAGE.exr EYE_X,EYE_Y,EYE_Z [FOV_DEG=40] [MAX_VIEW_DEG=75] [ERRORS.png]
// The camera must be splat-view's with that --eye, --target 0,0,0, --up 0,0,1 and --fov. For each
// pixel whose ray meets the sphere at a view angle (between the exact normal and the direction to
// the eye) below MAX_VIEW_DEG and whose N is non-zero, the angle between N (channels N.X, N.Y, N.Z)
// and the exact normal; prints their count, mean, p95 and maximum in degrees, and the pixels the
// sphere covers that the image leaves empty. ERRORS.png: the errors as grey levels, white = 5° or
// more.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "render/camera.h"

namespace {

bool parse_vec(const char* s, splatkit::Vec3f& v) {
  return std::sscanf(s, "%f,%f,%f", &v.x, &v.y, &v.z) == 3;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: bench_render_quality IMAGE.exr EYE_X,EYE_Y,EYE_Z [FOV_DEG] "
                 "[MAX_VIEW_DEG]\n");
    return 1;
  }
  const double max_view = argc > 4 ? std::atof(argv[4]) : 75.0;
  auto in = OIIO::ImageInput::open(argv[1]);
  if (!in) {
    std::fprintf(stderr, "bench_render_quality: %s: cannot open\n", argv[1]);
    return 1;
  }
  const OIIO::ImageSpec& spec = in->spec();
  const int w = spec.width, h = spec.height;
  int cx = -1;
  for (int c = 0; c < spec.nchannels; ++c)
    if (spec.channelnames[c] == "N.X") cx = c;
  if (cx < 0 || cx + 3 > spec.nchannels || spec.channelnames[cx + 1] != "N.Y" ||
      spec.channelnames[cx + 2] != "N.Z") {
    std::fprintf(stderr, "bench_render_quality: %s: no N.X N.Y N.Z channels\n", argv[1]);
    return 1;
  }
  std::vector<float> n(std::size_t(w) * h * 3);
  if (!in->read_image(0, 0, cx, cx + 3, OIIO::TypeDesc::FLOAT, n.data())) {
    std::fprintf(stderr, "bench_render_quality: %s: %s\n", argv[1], in->geterror().c_str());
    return 1;
  }
  splatkit::render::Camera cam;
  cam.width = w;
  cam.height = h;
  if (!parse_vec(argv[2], cam.eye)) {
    std::fprintf(stderr, "bench_render_quality: bad eye '%s'\n", argv[2]);
    return 1;
  }
  cam.target = {0, 0, 0};
  cam.up = {0, 0, 1};
  cam.fov_y_deg = argc > 3 ? std::atof(argv[3]) : 40.0;
  const splatkit::render::Projection pr = splatkit::render::make_projection(cam);
  const double kDeg = 180.0 / 3.14159265358979323846;
  std::vector<double> errors;
  std::vector<unsigned char> image(std::size_t(w) * h, 0);
  long empty = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const splatkit::Vec3f rf = pr.ray(x + 0.5f, y + 0.5f);
      const double d[3] = {rf.x, rf.y, rf.z}, o[3] = {pr.eye.x, pr.eye.y, pr.eye.z};
      const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
      const double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - 1;
      const double disc = b * b - dd * c;
      if (disc < 0) continue;
      const double t = (-b - std::sqrt(disc)) / dd;
      const double p[3] = {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]};
      const double pl = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      const double dl = std::sqrt(dd);
      const double cos_view = -(p[0] * d[0] + p[1] * d[1] + p[2] * d[2]) / (pl * dl);
      if (std::acos(std::clamp(cos_view, -1.0, 1.0)) * kDeg >= max_view) continue;
      const float* q = &n[3 * (std::size_t(y) * w + x)];
      const double ql = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2]);
      if (!(ql > 0)) {
        ++empty;
        continue;
      }
      const double cosang = (q[0] * p[0] + q[1] * p[1] + q[2] * p[2]) / (ql * pl);
      errors.push_back(std::acos(std::clamp(cosang, -1.0, 1.0)) * kDeg);
      image[std::size_t(y) * w + x] =
          static_cast<unsigned char>(std::min(255.0, errors.back() / 5.0 * 255.0 + 0.5));
    }
  if (errors.empty()) {
    std::fprintf(stderr, "bench_render_quality: %s: no pixel on the sphere\n", argv[1]);
    return 1;
  }
  if (argc > 5) {
    auto out = OIIO::ImageOutput::create(argv[5]);
    if (!out || !out->open(argv[5], OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::UINT8)) ||
        !out->write_image(OIIO::TypeDesc::UINT8, image.data()) || !out->close()) {
      std::fprintf(stderr, "bench_render_quality: %s: cannot write\n", argv[5]);
      return 1;
    }
  }
  double sum = 0;
  for (double e : errors) sum += e;
  std::sort(errors.begin(), errors.end());
  const double p95 = errors[std::min(errors.size() - 1, std::size_t(0.95 * errors.size()))];
  std::printf("pixels %zu, mean %.3f deg, p95 %.3f deg, max %.2f deg, empty %ld\n", errors.size(),
              sum / errors.size(), p95, errors.back(), empty);
  return 0;
}
