// The peer of build-ham in ham.sh: the same computation with OpenCV, I/O included: read the
// TIFF (cv::imread), Sobel magnitude twice (cv::Sobel 3×3 in x and y, BORDER_REPLICATE =
// clamp-to-edge, cv::magnitude), the per-tile maxima of HAM and height with the texel of the
// highest height, and write the tile records (raw floats and uint32) to a file.
// usage: bench_ham_opencv IN.tif OUT.bin TILE THREADS
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

cv::Mat sobel_magnitude(const cv::Mat& in) {
  cv::Mat dx, dy, m;
  cv::Sobel(in, dx, CV_32F, 0, 1, 3, 1, 0, cv::BORDER_REPLICATE);
  cv::Sobel(in, dy, CV_32F, 1, 0, 3, 1, 0, cv::BORDER_REPLICATE);
  cv::magnitude(dx, dy, m);
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: bench_ham_opencv IN.tif OUT.bin TILE THREADS\n");
    return 1;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const int tile = std::atoi(argv[3]);
  cv::setNumThreads(std::atoi(argv[4]));
  cv::Mat h = cv::imread(argv[1], cv::IMREAD_UNCHANGED);
  if (h.empty()) return 2;
  if (h.type() != CV_32F) h.convertTo(h, CV_32F);
  const cv::Mat ham = sobel_magnitude(sobel_magnitude(h));
  const int tx = (h.cols + tile - 1) / tile, ty = (h.rows + tile - 1) / tile;
  std::vector<float> ham_max(std::size_t(tx) * ty, 0), h_max(ham_max.size(), -INFINITY);
  std::vector<uint32_t> x_of(ham_max.size()), y_of(ham_max.size());
  cv::parallel_for_(cv::Range(0, ty), [&](const cv::Range& r) {
    for (int j = r.start; j < r.end; ++j)
      for (int i = 0; i < tx; ++i) {
        const cv::Rect rect(i * tile, j * tile, std::min(tile, h.cols - i * tile),
                            std::min(tile, h.rows - j * tile));
        double lo, hi;
        cv::Point at;
        cv::minMaxLoc(ham(rect), &lo, &hi);
        ham_max[std::size_t(j) * tx + i] = float(hi);
        cv::minMaxLoc(h(rect), &lo, &hi, nullptr, &at);
        h_max[std::size_t(j) * tx + i] = float(hi);
        x_of[std::size_t(j) * tx + i] = uint32_t(rect.x + at.x);
        y_of[std::size_t(j) * tx + i] = uint32_t(rect.y + at.y);
      }
  });
  FILE* f = std::fopen(argv[2], "wb");
  if (!f) return 2;
  std::fwrite(ham_max.data(), 4, ham_max.size(), f);
  std::fwrite(h_max.data(), 4, h_max.size(), f);
  std::fwrite(x_of.data(), 4, x_of.size(), f);
  std::fwrite(y_of.data(), 4, y_of.size(), f);
  std::fclose(f);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("opencv: %d x %d in %.3f s (%.1f M samples/s)\n", h.cols, h.rows, s,
              double(h.total()) / s / 1e6);
  return 0;
}
