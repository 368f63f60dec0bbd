// InputStream's large reads from a regular file, which go out as pieces read in parallel: the
// bytes, the running checksum and the position after them match a plain read, after a buffered
// start, across a short last piece, and when the file ends inside the read.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdint>

#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "splatkit/crc32c.h"
#include "splatkit/input_stream.h"

namespace splatkit {
namespace {

std::vector<char> random_bytes(std::size_t n, unsigned seed) {
  std::mt19937 g(seed);
  std::vector<char> b(n);
  for (char& c : b) c = static_cast<char>(g());
  return b;
}

std::string write_temp(const std::vector<char>& bytes) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("splatkit_input_stream_" + std::to_string(::getpid()) + ".bin"))
                               .string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  EXPECT_NE(f, nullptr);
  EXPECT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  std::fclose(f);
  return path;
}

TEST(InputStream, LargeReadsInParallelPiecesMatchTheFile) {
  // 8 MiB and more go out in parallel pieces of 4 MiB: 21 MiB + 5 bytes leave a short last one.
  const std::size_t big = (std::size_t{21} << 20) + 5;
  const std::vector<char> file = random_bytes(100 + big + 3000, 5);
  const std::string path = write_temp(file);
  {
    InputStream in(path);
    std::vector<char> head(100), body(big), tail(3000);
    in.read(head.data(), head.size());  // through the buffer, which then holds more
    in.read(body.data(), body.size());
    EXPECT_EQ(in.offset(), 100 + big);
    in.read(tail.data(), tail.size());  // the position after the parallel read is right
    EXPECT_TRUE(in.at_eof());
    std::vector<char> all = head;
    all.insert(all.end(), body.begin(), body.end());
    all.insert(all.end(), tail.begin(), tail.end());
    EXPECT_TRUE(all == file);
    EXPECT_EQ(in.checksum(), crc32c(0, file.data(), file.size()));
  }
  {
    // Asking for more than is left: the bytes up to the end, then nothing.
    InputStream in(path);
    std::vector<char> over(file.size() + (std::size_t{9} << 20));
    EXPECT_EQ(in.read_some(over.data(), over.size()), file.size());
    EXPECT_TRUE(std::equal(file.begin(), file.end(), over.begin()));
    EXPECT_EQ(in.read_some(over.data(), 1), 0u);
    EXPECT_EQ(in.checksum(), crc32c(0, file.data(), file.size()));
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace splatkit
