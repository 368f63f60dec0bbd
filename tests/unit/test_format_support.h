// Helpers shared by the format tests: private temp files, whole-file reads, and the check that a
// reader rejects input with the right error kind and a one-line message naming the problem.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "splatkit/error.h"

namespace splatkit::test {

// A path in a directory private to this process and test (created), e.g. for round trips.
inline std::string temp_path(const std::string& prefix, const std::string& name) {
  auto dir = std::filesystem::path(testing::TempDir()) /
             (prefix + "_" + std::to_string(::getpid()) + "_" +
              testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// read() must throw splatkit::Error of `kind` whose message is one line containing `phrase`.
template <class Read>
void expect_read_error(Read&& read, ErrorKind kind, const std::string& phrase) {
  try {
    read();
    FAIL() << "no error; expected '" << phrase << "'";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.kind(), kind) << what;
    EXPECT_NE(what.find(phrase), std::string::npos)
        << "message: " << what << "\nexpected phrase: " << phrase;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
  }
}

}  // namespace splatkit::test
