// serve/encode_view_model.h: the layout the viewer page reads, for each kind of file, with the
// values of the library's own readers; bad input is the readers' error.
#include "serve/encode_view_model.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <fstream>
#include <string>

#include "apps/run_build_qsplat.h"
#include "apps/run_build_spt.h"
#include "formats/read_cloud.h"
#include "formats/read_qsplat.h"
#include "formats/read_spt.h"
#include "render/render_scene.h"
#include "splatkit/error.h"
#include "splatkit/input_stream.h"

namespace splatkit::serve {
namespace {

const std::string kTorus = std::string(SPLATKIT_SOURCE_DIR) + "/data-samples/torus.ply";

struct Parsed {
  std::string bytes;
  nlohmann::json header;
  const char* data = nullptr;  // the data section
  std::size_t data_bytes = 0;
};

Parsed parse(std::string bytes) {
  Parsed p;
  p.bytes = std::move(bytes);
  const std::string& model = p.bytes;
  EXPECT_EQ(model.compare(0, 8, std::string("SKVIEW1\0", 8)), 0);
  uint32_t length = 0;
  for (int i = 0; i < 4; ++i)
    length |= static_cast<uint32_t>(static_cast<unsigned char>(model[8 + i])) << (8 * i);
  p.header = nlohmann::json::parse(model.substr(12, length));
  const std::size_t base = (12 + length + 3) & ~std::size_t{3};
  p.data = model.data() + base;
  p.data_bytes = model.size() - base;
  for (const auto& [name, a] : p.header["arrays"].items()) {
    EXPECT_EQ(a["offset"].get<std::size_t>() % 4, 0u) << name;
    EXPECT_LE(a["offset"].get<std::size_t>() + a["bytes"].get<std::size_t>(), p.data_bytes) << name;
  }
  return p;
}

template <class T>
T at(const Parsed& p, const std::string& array, std::size_t index) {
  T v;
  std::memcpy(&v,
              p.data + p.header["arrays"][array]["offset"].get<std::size_t>() + index * sizeof(T),
              sizeof(T));
  return v;
}

TEST(ServeEncodeViewModel, SplatsCarryTheRenderScenesArraysAndFraming) {
  const Parsed p = parse(encode_view_model(kTorus, "torus.ply"));
  render::RenderScene s = render::make_render_scene(read_cloud(kTorus).cloud, "torus.ply");
  EXPECT_EQ(p.header["kind"], "splats");
  EXPECT_EQ(p.header["name"], "torus.ply");
  ASSERT_EQ(p.header["count"].get<std::size_t>(), s.size());
  EXPECT_FLOAT_EQ(p.header["bounds"][3].get<float>(), s.bounds.radius);
  EXPECT_FLOAT_EQ(p.header["mean_radius"].get<float>(), s.mean_radius);
  EXPECT_EQ(p.header["arrays"]["position"]["bytes"].get<std::size_t>(), 12 * s.size());
  for (std::size_t i : {std::size_t{0}, s.size() / 2, s.size() - 1}) {
    EXPECT_EQ(at<float>(p, "position", 3 * i + 2), s.positions[i].z);
    EXPECT_EQ(at<float>(p, "normal", 3 * i), s.normals[i].x);
    EXPECT_EQ(at<float>(p, "radius", i), s.radii[i]);
  }
  EXPECT_FALSE(p.header["arrays"].contains("surface"));  // torus.ply has no surface ids
}

TEST(ServeEncodeViewModel, SptIsOneInterleavedListInFileOrder) {
  const std::string out = testing::TempDir() + "/view_model_torus.spt";
  apps::BuildSptOptions o;
  o.paths = {kTorus, out, ""};
  apps::run_build_spt(o);
  const Parsed p = parse(encode_view_model(out, "torus.spt"));
  InputStream in(out);
  const SptModel m = read_spt(in);
  EXPECT_EQ(p.header["kind"], "spt");
  ASSERT_EQ(p.header["count"].get<std::size_t>(), m.size());
  EXPECT_EQ(p.header["stride"], 36);
  EXPECT_FLOAT_EQ(p.header["epsilon"].get<float>(), m.header.epsilon);
  EXPECT_EQ(p.header["arrays"]["entries"]["bytes"].get<std::size_t>(), 36 * m.size());
  for (std::size_t i : {std::size_t{0}, m.size() / 3, m.size() - 1}) {
    EXPECT_EQ(at<float>(p, "entries", 9 * i), m.positions[i].x);
    EXPECT_EQ(at<float>(p, "entries", 9 * i + 5), m.diameters[i]);
    EXPECT_EQ(at<float>(p, "entries", 9 * i + 6), m.r_min[i]);
    EXPECT_EQ(at<float>(p, "entries", 9 * i + 7), std::min(m.r_max[i], 3.4e38f));
  }
}

TEST(ServeEncodeViewModel, QSplatKeepsTheTreeForTheTraversal) {
  const std::string out = testing::TempDir() + "/view_model_torus.qs";
  apps::BuildQSplatOptions o;
  o.paths = {kTorus, out, ""};
  apps::run_build_qsplat(o);
  const Parsed p = parse(encode_view_model(out, "torus.qs"));
  InputStream in(out);
  const QSplatModel m = read_qsplat(in);
  EXPECT_EQ(p.header["kind"], "qsplat");
  ASSERT_EQ(p.header["count"].get<std::size_t>(), m.size());
  EXPECT_EQ(p.header["leaves"].get<uint64_t>(), m.leaves);
  EXPECT_EQ(p.header["arrays"]["roots"]["bytes"].get<std::size_t>(), 4 * m.roots.size());
  for (std::size_t i : {std::size_t{0}, m.size() / 2, m.size() - 1}) {
    EXPECT_EQ(at<float>(p, "radius", i), m.radii[i]);
    EXPECT_EQ(at<uint32_t>(p, "first_child", i), m.first_child[i]);
    EXPECT_EQ(at<uint32_t>(p, "child_count", i), m.child_count[i]);
  }
}

TEST(ServeEncodeViewModel, BadInputIsTheReadersError) {
  const std::string bad = testing::TempDir() + "/view_model_bad.spt";
  std::ofstream(bad, std::ios::binary) << "not a splat file at all";
  try {
    encode_view_model(bad, "bad.spt");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(e.exit_code(), 0);
  }
}

}  // namespace
}  // namespace splatkit::serve
