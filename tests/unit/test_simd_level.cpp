// simd_level: the names, the caps (CPU, SPLATKIT_SIMD, a test's ScopedSimdLevel), and the error
// for a bad SPLATKIT_SIMD.
#include "splatkit/simd_level.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "splatkit/error.h"

namespace splatkit {
namespace {

TEST(SimdLevel, NamesRoundTrip) {
  for (SimdLevel level :
       {SimdLevel::kPortable, SimdLevel::kSse2, SimdLevel::kAvx2, SimdLevel::kAvx512})
    EXPECT_EQ(parse_simd_level(simd_level_name(level), "X"), level);
}

TEST(SimdLevel, BadNamesAreUsageErrorsNamingTheVariableAndTheChoices) {
  for (const char* bad : {"AVX2", "avx", "none", " portable", "avx512f", "sse4"}) {
    try {
      parse_simd_level(bad, "SPLATKIT_SIMD");
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::kUsage);
      const std::string what = e.what();
      EXPECT_NE(what.find(std::string("SPLATKIT_SIMD=") + bad), std::string::npos) << what;
      EXPECT_NE(what.find("portable, sse2, avx2, avx512"), std::string::npos) << what;
    }
  }
}

// The level in force is min(CPU, SPLATKIT_SIMD): run under SPLATKIT_SIMD=portable, this proves
// that the kernels (which all ask simd_level()) take their portable paths.
TEST(SimdLevel, FollowsTheCpuAndTheEnvironment) {
  SimdLevel expected = cpu_simd_level();
  const char* env = std::getenv("SPLATKIT_SIMD");
  if (env != nullptr && *env != '\0')
    expected = std::min(expected, parse_simd_level(env, "SPLATKIT_SIMD"));
  EXPECT_EQ(simd_level(), expected);
  std::printf("SIMD: this CPU offers %s; SPLATKIT_SIMD=%s; the kernels use %s\n",
              simd_level_name(cpu_simd_level()), env ? env : "(unset)",
              simd_level_name(simd_level()));
#if defined(__x86_64__)
  EXPECT_GE(cpu_simd_level(), SimdLevel::kSse2);  // part of x86-64
  EXPECT_EQ(cpu_simd_level() >= SimdLevel::kAvx2, __builtin_cpu_supports("avx2") != 0);
#endif
}

TEST(SimdLevel, ScopedCapsNestAndRestore) {
  const SimdLevel before = simd_level();
  {
    ScopedSimdLevel cap(SimdLevel::kPortable);
    EXPECT_EQ(simd_level(), SimdLevel::kPortable);
    {
      ScopedSimdLevel inner(SimdLevel::kAvx512);  // a cap never raises the level past the CPU's
      EXPECT_EQ(simd_level(), before);
    }
    EXPECT_EQ(simd_level(), SimdLevel::kPortable);
  }
  EXPECT_EQ(simd_level(), before);
}

}  // namespace
}  // namespace splatkit
