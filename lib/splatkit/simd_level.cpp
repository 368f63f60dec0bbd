#include "splatkit/simd_level.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <optional>

#include "splatkit/error.h"

namespace splatkit {
namespace {

constexpr const char* kNames[] = {"portable", "sse2", "avx2", "avx512"};

// The test cap; kAvx512 when none.
std::atomic<SimdLevel> test_cap{SimdLevel::kAvx512};

// SPLATKIT_SIMD's cap, or the error its value gives (read once).
struct EnvCap {
  SimdLevel level = SimdLevel::kAvx512;
  std::optional<Error> error;
};

EnvCap read_env_cap() {
  EnvCap cap;
  const char* value = std::getenv("SPLATKIT_SIMD");
  if (value == nullptr || *value == '\0') return cap;
  try {
    cap.level = parse_simd_level(value, "SPLATKIT_SIMD");
  } catch (const Error& e) {
    cap.error = e;
  }
  return cap;
}

}  // namespace

SimdLevel cpu_simd_level() {
#if defined(__x86_64__)
  static const SimdLevel best = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx2")
                                    ? SimdLevel::kAvx512
                                : __builtin_cpu_supports("avx2") ? SimdLevel::kAvx2
                                                                 : SimdLevel::kSse2;
  return best;
#else
  return SimdLevel::kPortable;
#endif
}

SimdLevel simd_level() {
  static const EnvCap env = read_env_cap();
  if (env.error) throw *env.error;
  return std::min({cpu_simd_level(), env.level, test_cap.load(std::memory_order_relaxed)});
}

const char* simd_level_name(SimdLevel level) { return kNames[static_cast<int>(level)]; }

SimdLevel parse_simd_level(std::string_view name, const std::string& what) {
  for (int i = 0; i < 4; ++i)
    if (name == kNames[i]) return static_cast<SimdLevel>(i);
  throw Error(ErrorKind::kUsage, what + "=" + std::string(name) +
                                     ": not one of portable, sse2, avx2, avx512 (or unset for the "
                                     "best this CPU runs)");
}

ScopedSimdLevel::ScopedSimdLevel(SimdLevel cap) : previous_(test_cap.exchange(cap)) {}

ScopedSimdLevel::~ScopedSimdLevel() { test_cap.store(previous_); }

}  // namespace splatkit
