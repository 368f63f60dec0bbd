// SimdLevel: which vector code splatkit's kernels may run, chosen once per process.
//
// Every kernel with a vector path (SpatialIndex's batch kNN and sphere overlaps,
// graph::sphere_overlap_graph) asks simd_level() and takes the best path it has at or below that
// level; the portable path is plain C++ and the one to read to learn an algorithm. All paths give
// bit-identical results, so the level changes only the speed.
//
// simd_level() = min(the CPU's best, the cap in the environment variable SPLATKIT_SIMD, a test's
// ScopedSimdLevel cap). SPLATKIT_SIMD is one of "portable", "sse2", "avx2", "avx512" (unset or
// empty: no cap); it is read once, on the first call. Any other value throws
// Error(ErrorKind::kUsage) naming the variable and the accepted values, on that call and on
// every later one. Thread-safe.
#pragma once

#include <string>
#include <string_view>

namespace splatkit {

// Ordered: a level includes the ones before it. kAvx512 means AVX-512F (with AVX2).
enum class SimdLevel { kPortable, kSse2, kAvx2, kAvx512 };

// The best level this CPU runs (kPortable off x86-64), asked once.
SimdLevel cpu_simd_level();

// The level the kernels use now (see above).
SimdLevel simd_level();

// "portable", "sse2", "avx2", "avx512".
const char* simd_level_name(SimdLevel level);

// The level named `name` (simd_level_name's spelling); throws Error(ErrorKind::kUsage) naming
// `what` (e.g. "SPLATKIT_SIMD") and the accepted names otherwise.
SimdLevel parse_simd_level(std::string_view name, const std::string& what);

// For tests: a cap on simd_level() while it lives, replacing the previous test cap, which comes
// back at its end (process-wide: one test at a time).
class ScopedSimdLevel {
 public:
  explicit ScopedSimdLevel(SimdLevel cap);
  ~ScopedSimdLevel();
  ScopedSimdLevel(const ScopedSimdLevel&) = delete;
  ScopedSimdLevel& operator=(const ScopedSimdLevel&) = delete;

 private:
  SimdLevel previous_;
};

}  // namespace splatkit
