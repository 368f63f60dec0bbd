// read_cloud's progress: fractions of the file read, rising to 1, on a real file of every
// streamed format; a callback that throws Cancelled stops the read at once.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "formats/read_cloud.h"
#include "formats/write_cloud.h"
#include "splatkit/progress.h"
#include "test_format_support.h"

namespace splatkit {
namespace {

// A cloud of n points with normals and colours: a few MB on disk in any format.
LoadedCloud sample_cloud(std::size_t n) {
  LoadedCloud doc;
  SplatCloud& c = doc.cloud;
  for (std::size_t i = 0; i < n; ++i) {
    const float t = static_cast<float>(i);
    c.positions.push_back({t * 0.001f, std::sin(t) * 3.0f, std::cos(t * 0.37f)});
    c.normals.push_back({0, 0, 1});
    c.colors.push_back({static_cast<uint16_t>(i % 256), 7, 9});
  }
  return doc;
}

std::string write_sample(const std::string& name, FileFormat format) {
  const std::string path = test::temp_path("progress", name);
  WriteOptions w;
  w.format = format;
  write_cloud(sample_cloud(200000), path, w);
  return path;
}

struct Report {
  double fraction;
  std::string phase;
};

class ReadCloudProgress : public testing::TestWithParam<std::pair<const char*, FileFormat>> {};

TEST_P(ReadCloudProgress, FractionsRiseToOne) {
  const std::string path = write_sample(GetParam().first, GetParam().second);
  std::vector<Report> seen;
  const LoadedCloud doc = read_cloud(path, {}, [&](double f, const char* phase) {
    seen.push_back({f, phase});
  });
  EXPECT_EQ(doc.cloud.size(), 200000u);
  ASSERT_GE(seen.size(), 3u) << "a multi-megabyte file reports along the way";
  EXPECT_LT(seen.front().fraction, 0.5);
  for (std::size_t i = 1; i < seen.size(); ++i) {
    EXPECT_GE(seen[i].fraction, seen[i - 1].fraction) << i;
    EXPECT_GE(seen[i].fraction, 0.0);
  }
  EXPECT_EQ(seen.back().fraction, 1.0);
  EXPECT_EQ(seen.back().phase, "reading");
}

INSTANTIATE_TEST_SUITE_P(Formats, ReadCloudProgress,
                         testing::Values(std::pair{"p.ply", FileFormat::kPly},
                                         std::pair{"p.xyz", FileFormat::kXyz},
                                         std::pair{"p.off", FileFormat::kOff},
                                         std::pair{"p.splk", FileFormat::kSplk}));

TEST(ReadCloudProgressCancel, CancelledStopsTheReadAtOnce) {
  const std::string path = write_sample("c.ply", FileFormat::kPly);
  int calls = 0;
  double last = -1;
  EXPECT_THROW(read_cloud(path, {},
                          [&](double f, const char*) {
                            ++calls;
                            last = f;
                            if (f > 0.2) throw Cancelled();
                          }),
               Cancelled);
  EXPECT_GT(last, 0.2);
  EXPECT_LT(last, 0.5) << "the read stopped at the first report past 20 %";
  // The stream reports nothing once read_cloud has returned: a second read reports afresh.
  InputStream in(path);
  int again = 0;
  read_cloud(in, {}, [&](double, const char*) { ++again; });
  EXPECT_GT(again, 0);
  EXPECT_GT(calls, 0);
}

TEST(ReadCloudProgressCancel, PipeReportsBytesSoFar) {
  const std::string bytes = test::slurp(write_sample("pipe.xyz", FileFormat::kXyz));
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  std::thread writer([&] {
    for (std::size_t off = 0; off < bytes.size();) {
      const ssize_t n = ::write(fds[1], bytes.data() + off, bytes.size() - off);
      if (n <= 0) break;
      off += static_cast<std::size_t>(n);
    }
    ::close(fds[1]);
  });
  std::vector<Report> seen;
  {
    InputStream in("/dev/fd/" + std::to_string(fds[0]));
    EXPECT_FALSE(in.size_hint().has_value());
    const LoadedCloud doc = read_cloud(in, {}, [&](double f, const char* phase) {
      seen.push_back({f, phase});
    });
    EXPECT_EQ(doc.cloud.size(), 200000u);
  }
  writer.join();
  ::close(fds[0]);
  ASSERT_GE(seen.size(), 3u);
  for (std::size_t i = 0; i + 1 < seen.size(); ++i) {
    EXPECT_LT(seen[i].fraction, 0.0) << "no fraction without a size";
    EXPECT_EQ(seen[i].phase.rfind("read ", 0), 0u) << seen[i].phase;
    EXPECT_NE(seen[i].phase.find(" MiB"), std::string::npos) << seen[i].phase;
  }
  EXPECT_EQ(seen.back().fraction, 1.0);
}

}  // namespace
}  // namespace splatkit
