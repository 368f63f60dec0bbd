// Clip-partner classification and the fragment rule: [IvoMSc] §4.3–§4.4 in docs/references.md
// (eqs. 4.13–4.18, fig. 4.5) on constructed configurations whose correct discard regions are known
// from the geometry, and the per-surface extension at corners ([IvoMSc] §7.3).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "graph/classify_clip_partners.h"
#include "graph/clip_record.h"

namespace splatkit::graph {
namespace {

struct Config {
  Vec3f c, n;
  std::vector<Vec3f> centres, normals;
  std::vector<uint32_t> surfaces;  // empty: [IvoMSc]'s single set
};

ClipClassification classify(const Config& cfg, double tol = 1e-4) {
  ClipClassification out;
  classify_clip_partners(cfg.c, cfg.n, cfg.centres, cfg.normals, cfg.surfaces, tol, out);
  return out;
}

bool discarded(const Config& cfg, const ClipClassification& cls, const Vec3f& p) {
  std::vector<ClipPlane> planes;
  for (std::size_t k = 0; k < cls.order.size(); ++k)
    planes.push_back(
        make_clip_plane(cfg.centres[cls.order[k]], cfg.normals[cls.order[k]], cls.flags[k]));
  ClipView view{planes.data(), cls.flags.data(), static_cast<uint32_t>(planes.size()),
                cls.combine_intersection};
  return fragment_discarded(view, p);
}

Vec3f polar(double r, double degrees, float z = 0) {
  const double a = degrees * std::numbers::pi / 180;
  return {float(r * std::cos(a)), float(r * std::sin(a)), z};
}

// A vertical cylinder of radius 2 about the z axis (a round pillar, or a round hole/room when
// the normals point inwards) with two partner splats at ±30°, height z; S lies in z = 0 at
// distance s_r from the axis with normal +z.
Config cylinder_case(double s_r, float partner_z, bool outward) {
  Config cfg;
  cfg.c = polar(s_r, 0);
  cfg.n = {0, 0, 1};
  for (double deg : {30.0, -30.0}) {
    cfg.centres.push_back(polar(2, deg, partner_z));
    const Vec3f out = polar(1, deg);
    cfg.normals.push_back(outward ? out : -out);
  }
  return cfg;
}

TEST(GraphClipRule, SeedTable) {  // [IvoMSc] eq. 4.15
  EXPECT_EQ(clip_rule(Convexity::kConcave, ClipSide::kBehind), ClipRule::kUnion);
  EXPECT_EQ(clip_rule(Convexity::kConcave, ClipSide::kFront), ClipRule::kIntersection);
  EXPECT_EQ(clip_rule(Convexity::kConvex, ClipSide::kBehind), ClipRule::kIntersection);
  EXPECT_EQ(clip_rule(Convexity::kConvex, ClipSide::kFront), ClipRule::kUnion);
  EXPECT_EQ(clip_rule(Convexity::kFlat, ClipSide::kFront), ClipRule::kUnion);
  EXPECT_EQ(clip_rule(Convexity::kMixed, ClipSide::kBehind), ClipRule::kIntersection);
}

TEST(GraphClipClassification, ConcaveConcaveRoundRoom) {
  // Fig. 4.5a: S on the floor of a round room, partners on its wall (normals towards the axis)
  // above the floor. The wall material (r > 2) is the union of the areas behind the partners.
  const Config cfg = cylinder_case(1.875, 0.125f, false);
  EXPECT_EQ(partner_set_convexity(cfg.centres, cfg.normals, 1e-4), Convexity::kConcave);
  EXPECT_EQ(splat_partner_convexity(cfg.c, cfg.n, cfg.centres, 1e-4), Convexity::kConcave);
  const auto cls = classify(cfg);
  ASSERT_EQ(cls.subsets.size(), 1u);
  EXPECT_EQ(cls.subsets[0].rule, ClipRule::kUnion);
  EXPECT_EQ(cls.flags[0] & kClipFront, 0);
  EXPECT_TRUE(discarded(cfg, cls, polar(2.5, 60)));   // in the wall, behind one partner only
  EXPECT_TRUE(discarded(cfg, cls, polar(2.5, 0)));    // behind both
  EXPECT_FALSE(discarded(cfg, cls, polar(1.5, 0)));   // the floor
  EXPECT_FALSE(discarded(cfg, cls, polar(1.9, 60)));  // the floor
}

TEST(GraphClipClassification, ConcaveConvexBoreInPlate) {
  // Fig. 4.5c: S on a plate next to a round hole, partners on the hole's wall below the plate.
  // The hole (r < 2) is the intersection of the areas in front of the partners.
  const Config cfg = cylinder_case(2.125, -0.125f, false);
  EXPECT_EQ(partner_set_convexity(cfg.centres, cfg.normals, 1e-4), Convexity::kConcave);
  EXPECT_EQ(splat_partner_convexity(cfg.c, cfg.n, cfg.centres, 1e-4), Convexity::kConvex);
  const auto cls = classify(cfg);
  EXPECT_EQ(cls.subsets[0].rule, ClipRule::kIntersection);
  EXPECT_EQ(cls.flags[0] & kClipFront, kClipFront);
  EXPECT_TRUE(discarded(cfg, cls, polar(1.9, 60)));   // over the hole
  EXPECT_FALSE(discarded(cfg, cls, polar(2.5, 60)));  // plate, in front of one partner only
  EXPECT_FALSE(discarded(cfg, cls, polar(2.5, 0)));   // plate
}

TEST(GraphClipClassification, ConvexConcavePillarOnFloor) {
  // Fig. 4.5e: S on the floor next to a round pillar, partners on the pillar above the floor.
  // The pillar (r < 2) is the intersection of the areas behind the partners.
  const Config cfg = cylinder_case(2.125, 0.125f, true);
  EXPECT_EQ(partner_set_convexity(cfg.centres, cfg.normals, 1e-4), Convexity::kConvex);
  EXPECT_EQ(splat_partner_convexity(cfg.c, cfg.n, cfg.centres, 1e-4), Convexity::kConcave);
  const auto cls = classify(cfg);
  EXPECT_EQ(cls.subsets[0].rule, ClipRule::kIntersection);
  EXPECT_EQ(cls.flags[0] & kClipFront, 0);
  EXPECT_TRUE(discarded(cfg, cls, polar(1.9, 60)));   // inside the pillar
  EXPECT_FALSE(discarded(cfg, cls, polar(2.5, 60)));  // floor, behind one partner only
  EXPECT_FALSE(discarded(cfg, cls, polar(2.5, 0)));   // floor
}

TEST(GraphClipClassification, ConvexConvexPillarTop) {
  // Fig. 4.5g: S on the top of a round pillar, partners on its side below the top. The air
  // around the pillar (r > 2) is the union of the areas in front of the partners.
  const Config cfg = cylinder_case(1.875, -0.125f, true);
  EXPECT_EQ(partner_set_convexity(cfg.centres, cfg.normals, 1e-4), Convexity::kConvex);
  EXPECT_EQ(splat_partner_convexity(cfg.c, cfg.n, cfg.centres, 1e-4), Convexity::kConvex);
  const auto cls = classify(cfg);
  EXPECT_EQ(cls.subsets[0].rule, ClipRule::kUnion);
  EXPECT_EQ(cls.flags[0] & kClipFront, kClipFront);
  EXPECT_TRUE(discarded(cfg, cls, polar(2.5, 60)));   // beyond the rim, past one partner only
  EXPECT_FALSE(discarded(cfg, cls, polar(1.9, 60)));  // the top
  EXPECT_FALSE(discarded(cfg, cls, polar(1.5, 0)));   // the top
}

TEST(GraphClipClassification, StraightCreasesAreFlat) {
  // L-shaped concave crease: floor z = 0 (S) and wall x = 0 facing +x (solid at x < 0).
  Config floor_wall;
  floor_wall.c = {0.125f, 0, 0};
  floor_wall.n = {0, 0, 1};
  floor_wall.centres = {{0, -0.25f, 0.125f}, {0, 0.25f, 0.125f}};
  floor_wall.normals = {{1, 0, 0}, {1, 0, 0}};
  auto cls = classify(floor_wall);
  EXPECT_EQ(cls.subsets[0].partners, Convexity::kFlat);
  EXPECT_EQ(cls.subsets[0].splat, Convexity::kConcave);
  EXPECT_TRUE(discarded(floor_wall, cls, {-0.0625f, 0, 0}));  // inside the wall
  EXPECT_FALSE(discarded(floor_wall, cls, {0.0625f, 0.3f, 0}));

  // Convex box edge: top z = 0 (S) of a box at x < 0, side x = 0 facing +x below the top.
  Config box_edge = floor_wall;
  box_edge.c = {-0.125f, 0, 0};
  box_edge.centres = {{0, -0.25f, -0.125f}, {0, 0.25f, -0.125f}};
  cls = classify(box_edge);
  EXPECT_EQ(cls.subsets[0].partners, Convexity::kFlat);
  EXPECT_EQ(cls.subsets[0].splat, Convexity::kConvex);
  EXPECT_TRUE(discarded(box_edge, cls, {0.0625f, 0, 0}));  // beyond the edge, in the air
  EXPECT_FALSE(discarded(box_edge, cls, {-0.0625f, -0.3f, 0}));
}

TEST(GraphClipClassification, ToleranceSeparatesFlatFromCurved) {
  // Partners 1e-3 off a common plane: flat with tol 1e-2, mixed (bumpy) with tol 1e-5.
  const std::vector<Vec3f> c{{0, -1, 0.001f}, {0, 1, 0.001f}, {0, 0, -0.002f}};
  const std::vector<Vec3f> n(3, Vec3f{0, 0, 1});
  EXPECT_EQ(partner_set_convexity(c, n, 1e-2), Convexity::kFlat);
  EXPECT_EQ(partner_set_convexity(c, n, 1e-5), Convexity::kMixed);
  EXPECT_EQ(partner_set_convexity(std::vector<Vec3f>{{0, 0, 0}}, std::vector<Vec3f>{{0, 0, 1}}, 0),
            Convexity::kFlat);
  EXPECT_THROW(partner_set_convexity(c, std::vector<Vec3f>{{0, 0, 1}}, 0), std::invalid_argument);
}

// Cube [-1, 1]³, corner (1, 1, 1). S on face A (x = 1) near the corner; partners on faces
// B (y = 1) and C (z = 1), surface ids 1 and 2. S must lose what lies beyond B's plane and
// what lies beyond C's plane.
Config cube_corner(bool with_surfaces) {
  Config cfg;
  cfg.c = {1, 0.875f, 0.875f};
  cfg.n = {1, 0, 0};
  cfg.centres = {
      {0.875f, 1, 0.875f}, {0.875f, 0.875f, 1}, {0.875f, 1, 0.625f}, {0.875f, 0.625f, 1}};
  cfg.normals = {{0, 1, 0}, {0, 0, 1}, {0, 1, 0}, {0, 0, 1}};
  if (with_surfaces) cfg.surfaces = {1, 2, 1, 2};
  return cfg;
}

TEST(GraphClipClassification, CubeCornerPerSurface) {
  const Config cfg = cube_corner(true);
  const auto cls = classify(cfg);
  ASSERT_EQ(cls.subsets.size(), 2u);
  EXPECT_EQ(cls.order, (std::vector<uint32_t>{0, 2, 1, 3}));  // grouped by surface, stable
  for (const auto& s : cls.subsets) {
    EXPECT_EQ(s.partners, Convexity::kFlat);
    EXPECT_EQ(s.splat, Convexity::kConvex);
    EXPECT_EQ(s.rule, ClipRule::kUnion);
  }
  EXPECT_EQ(cls.flags, (std::vector<uint8_t>{kClipFront | kClipSubsetStart, kClipFront,
                                             kClipFront | kClipSubsetStart, kClipFront}));
  EXPECT_EQ(cls.subsets_convexity, Convexity::kConvex);
  EXPECT_FALSE(cls.combine_intersection);
  EXPECT_FALSE(discarded(cfg, cls, {1, 0.9375f, 0.9375f}));  // on the face
  EXPECT_TRUE(discarded(cfg, cls, {1, 1.0625f, 0.9375f}));   // beyond B only
  EXPECT_TRUE(discarded(cfg, cls, {1, 0.9375f, 1.0625f}));   // beyond C only
  EXPECT_TRUE(discarded(cfg, cls, {1, 1.0625f, 1.0625f}));   // beyond both
  // [IvoMSc]'s single set classifies this corner too (convex/convex, union): same decisions.
  const Config seed_cfg = cube_corner(false);
  const auto seed = classify(seed_cfg);
  ASSERT_EQ(seed.subsets.size(), 1u);
  EXPECT_EQ(seed.subsets[0].partners, Convexity::kConvex);
  EXPECT_EQ(seed.subsets[0].rule, ClipRule::kUnion);
  for (const Vec3f& p :
       {Vec3f{1, 0.9375f, 0.9375f}, Vec3f{1, 1.0625f, 0.9375f}, Vec3f{1, 0.9375f, 1.0625f}})
    EXPECT_EQ(discarded(seed_cfg, seed, p), discarded(cfg, cls, p));
}

// A box [-1, 1]² × [0, 2] standing on the floor z = 0. S on the box's face A (x = 1) near the
// floor and near face B (y = 1): S sees the floor partners (concave crease) but not B's
// (convex edge) — [IvoMSc]'s failing case (§7.3). S must lose what is below the floor and what
// is beyond B.
Config box_on_floor(bool with_surfaces) {
  Config cfg;
  cfg.c = {1, 0.875f, 0.125f};
  cfg.n = {1, 0, 0};
  cfg.centres = {
      {1.125f, 0.875f, 0}, {1.125f, 0.625f, 0}, {0.875f, 1, 0.125f}, {0.875f, 1, 0.375f}};
  cfg.normals = {{0, 0, 1}, {0, 0, 1}, {0, 1, 0}, {0, 1, 0}};
  if (with_surfaces) cfg.surfaces = {7, 7, 3, 3};
  return cfg;
}

TEST(GraphClipClassification, MixedCornerSeedFailsPerSurfaceWorks) {
  const Config seed_cfg = box_on_floor(false);
  const auto seed = classify(seed_cfg);
  ASSERT_EQ(seed.subsets.size(), 1u);
  EXPECT_EQ(seed.subsets[0].partners, Convexity::kMixed);
  EXPECT_EQ(seed.subsets[0].splat, Convexity::kMixed);
  const Vec3f below_floor{1, 0.875f, -0.0625f}, beyond_b{1, 1.0625f, 0.125f};
  const Vec3f on_face{1, 0.875f, 0.125f};
  // [IvoMSc]'s method cannot classify the set. The fallback (one side for the whole set from the
  // symmetric test, intersection for a mixed set) removes the piece beyond B but keeps the piece
  // below the floor.
  EXPECT_EQ(seed.subsets[0].rule, ClipRule::kIntersection);
  EXPECT_FALSE(discarded(seed_cfg, seed, below_floor));
  EXPECT_TRUE(discarded(seed_cfg, seed, beyond_b));

  const Config cfg = box_on_floor(true);
  const auto cls = classify(cfg);
  ASSERT_EQ(cls.subsets.size(), 2u);
  EXPECT_EQ(cls.subsets[0].surface, 3u);  // B first: ascending surface id
  EXPECT_EQ(cls.subsets[0].splat, Convexity::kConvex);
  EXPECT_EQ(cls.subsets[1].splat, Convexity::kConcave);
  EXPECT_FALSE(cls.combine_intersection);
  EXPECT_TRUE(discarded(cfg, cls, below_floor));
  EXPECT_TRUE(discarded(cfg, cls, beyond_b));
  EXPECT_FALSE(discarded(cfg, cls, on_face));
  EXPECT_FALSE(discarded(cfg, cls, {1, 0.5f, 0.0625f}));
}

TEST(GraphClipClassification, FloorAtOuterBoxEdgeCombinesByIntersection) {
  // S on the floor next to the vertical edge x = y = 1 of the same box; partners on faces
  // x = 1 (surface 1) and y = 1 (surface 2), both seen by S. Only what is inside the box (behind
  // both faces) goes; "discard if any surface's rule discards" would cut the floor in front of
  // each face.
  Config cfg;
  cfg.c = {1.125f, 1.125f, 0};
  cfg.n = {0, 0, 1};
  cfg.centres = {
      {1, 0.875f, 0.125f}, {1, 0.625f, 0.125f}, {0.875f, 1, 0.125f}, {0.625f, 1, 0.125f}};
  cfg.normals = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}};
  cfg.surfaces = {1, 1, 2, 2};
  const auto cls = classify(cfg);
  EXPECT_EQ(cls.subsets_convexity, Convexity::kConvex);
  EXPECT_TRUE(cls.combine_intersection);
  EXPECT_TRUE(discarded(cfg, cls, {0.9375f, 0.9375f, 0}));   // inside the box
  EXPECT_FALSE(discarded(cfg, cls, {0.9375f, 1.0625f, 0}));  // floor in front of y = 1
  EXPECT_FALSE(discarded(cfg, cls, {1.0625f, 0.9375f, 0}));  // floor in front of x = 1
  EXPECT_FALSE(discarded(cfg, cls, {1.0625f, 1.0625f, 0}));
}

TEST(GraphClipClassification, RoomCornerCombinesByUnion) {
  // Inside corner of a room: floor S, walls x = 0 and y = 0 facing into the room.
  Config cfg;
  cfg.c = {0.125f, 0.125f, 0};
  cfg.n = {0, 0, 1};
  cfg.centres = {
      {0, 0.125f, 0.125f}, {0, 0.375f, 0.125f}, {0.125f, 0, 0.125f}, {0.375f, 0, 0.125f}};
  cfg.normals = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}};
  cfg.surfaces = {4, 4, 5, 5};
  const auto cls = classify(cfg);
  EXPECT_EQ(cls.subsets_convexity, Convexity::kConcave);
  EXPECT_FALSE(cls.combine_intersection);
  EXPECT_TRUE(discarded(cfg, cls, {-0.0625f, 0.125f, 0}));  // in wall x = 0 only
  EXPECT_TRUE(discarded(cfg, cls, {0.125f, -0.0625f, 0}));  // in wall y = 0 only
  EXPECT_FALSE(discarded(cfg, cls, {0.0625f, 0.0625f, 0}));
}

TEST(GraphClipClassification, EmptyAndMismatchedInputs) {
  ClipClassification out;
  classify_clip_partners({0, 0, 0}, {0, 0, 1}, {}, {}, {}, 0, out);
  EXPECT_TRUE(out.order.empty());
  EXPECT_TRUE(out.subsets.empty());
  const std::vector<Vec3f> one{{1, 0, 0}};
  const std::vector<uint32_t> two{1, 2};
  EXPECT_THROW(classify_clip_partners({0, 0, 0}, {0, 0, 1}, one, one, two, 0, out),
               std::invalid_argument);
}

}  // namespace
}  // namespace splatkit::graph
