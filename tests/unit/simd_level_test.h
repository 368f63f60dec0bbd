// SimdLevelTest: a fixture for tests that run a vector kernel at each SIMD level and compare it
// with an exact answer (instantiate with kEverySimdLevel). A level above what this CPU runs, or
// above SPLATKIT_SIMD's cap, is skipped loudly: a line on stdout and GTEST_SKIP's message name
// it. The test body runs with simd_level() capped at GetParam().
#pragma once

#include <gtest/gtest.h>

#include <cstdio>
#include <optional>
#include <string>

#include "splatkit/simd_level.h"

namespace splatkit {

inline const auto kEverySimdLevel =
    ::testing::Values(SimdLevel::kPortable, SimdLevel::kSse2, SimdLevel::kAvx2, SimdLevel::kAvx512);

inline std::string simd_level_param_name(const ::testing::TestParamInfo<SimdLevel>& info) {
  return simd_level_name(info.param);
}

class SimdLevelTest : public ::testing::TestWithParam<SimdLevel> {
 protected:
  void SetUp() override {
    const SimdLevel available = simd_level();
    if (GetParam() > available) {
      const std::string why = std::string("SIMD level ") + simd_level_name(GetParam()) +
                              " not run: this CPU offers " + simd_level_name(cpu_simd_level()) +
                              ", the cap allows " + simd_level_name(available);
      std::printf("[ SKIPPED  ] %s\n", why.c_str());
      GTEST_SKIP() << why;
    }
    cap_.emplace(GetParam());
  }
  void TearDown() override { cap_.reset(); }
  SimdLevel level() const { return GetParam(); }

 private:
  std::optional<ScopedSimdLevel> cap_;
};

}  // namespace splatkit
