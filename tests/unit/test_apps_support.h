// Helpers shared by the tests of lib/apps: files made by the stages themselves in a private temp
// directory (test_format_support.h), and the check that a stage fails with the right kind and a
// message naming the problem.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "apps/run_splat_synth.h"
#include "formats/read_cloud.h"
#include "splatkit/error.h"
#include "test_format_support.h"

namespace splatkit::test {

// A synthetic shape written to `path` (random sampling with noise unless told otherwise).
inline void synth(const std::string& shape, const std::string& path, std::size_t points = 3000,
                  double noise = 0.002, bool random = true, uint64_t seed = 7) {
  apps::SplatSynthOptions o;
  o.shape = shape;
  o.output = path;
  o.sample.points = points;
  o.sample.noise = noise;
  o.sample.random = random;
  o.sample.seed = seed;
  apps::run_splat_synth(o);
}

// run() must throw Error of `kind` whose one-line message contains `phrase`.
template <class Run>
void expect_stage_error(Run&& run, ErrorKind kind, const std::string& phrase) {
  expect_read_error(std::forward<Run>(run), kind, phrase);
}

}  // namespace splatkit::test
