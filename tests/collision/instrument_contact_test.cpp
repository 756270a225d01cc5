// SPDX-License-Identifier: MIT
#include "collision/instrument_contact.h"

#include "geometry/input_error.h"
#include "geometry/mesh_topology.h"
#include "geometry/shape_meshes.h"
#include "tests/collision/bvh_test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench::collision {
namespace {

using test::icosphere;
using ::testing::HasSubstr;

// A tool in millimetres beside tissue in metres is a thousand times larger than meant: sampled at
// the tissue's edge spacing it would take a million times the points. Refused with the limit,
// before any allocation, not run out of memory or time.
TEST(InstrumentContact, RefusesAToolThatWouldTakeMoreThanTheSampleLimit) {
  const TriMesh tissue = icosphere(2, 0.01);  // 1 cm, edges about 3 mm
  const TriMesh probe = icosphere(1, 0.002);
  EXPECT_NO_THROW(InstrumentContact(tissue.vertices, tissue.triangles, probe));
  TriMesh millimetres = probe;
  millimetres.vertices *= 1000.0;
  try {
    InstrumentContact contact(tissue.vertices, tissue.triangles, millimetres);
    FAIL() << "a tool needing billions of contact points was accepted";
  } catch (const InputError& error) {
    // The harness puts the instrument's file before it.
    EXPECT_STREQ(error.what(),
                 "InstrumentContact: the instrument mesh would take 439966922 candidate contact "
                 "points at the tissue's edge spacing (0.001492 m), more than the limit of "
                 "2000000: is it in other units than the tissue (millimetres beside metres)?");
  }
}

// The inside/outside signs need closed, consistently oriented surfaces: anything else is refused
// with the offending mesh named, not simulated with meaningless signs.
TEST(InstrumentContact, RefusesOpenOrMisorientedSurfaces) {
  const TriMesh tissue = icosphere(2, 1.0);
  const TriMesh instrument = icosphere(1, 0.2);
  EXPECT_NO_THROW(InstrumentContact(tissue.vertices, tissue.triangles, instrument));

  const Eigen::Matrix3Xi open = tissue.triangles.leftCols(tissue.triangles.cols() - 1);
  try {
    InstrumentContact contact(tissue.vertices, open, instrument);
    FAIL() << "an open tissue surface was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("tissue surface"));
    EXPECT_THAT(error.what(), HasSubstr("3 boundary"));
  }

  TriMesh flipped = instrument;
  flipped.triangles.col(0).reverseInPlace();
  try {
    InstrumentContact contact(tissue.vertices, tissue.triangles, flipped);
    FAIL() << "a misoriented instrument was accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("instrument mesh"));
    EXPECT_THAT(error.what(), HasSubstr("3 misoriented"));
  }
}

// The inside test of a point against the tissue's surface (the nearest feature's pseudonormal)
// says inside wherever the nearest triangle faces away from it; on an inverted patch that is the
// wrong side. An instrument point there is behind a fold, not in the tissue, and pushes nothing:
// pushing the patch "out" to it would move the tissue by the point's whole distance in one step
// (a crumpling liver's corner went 10 cm up with the withdrawing probe).
TEST(InstrumentContact, APointBehindAnInvertedPatchOfTheTissuePushesNothing) {
  // Two 4 x 4 x 2 cm slabs of 5 mm cells, the second 5 cm above the first.
  const MeshData slab = box_tets(8, 8, 4, 0.04, 0.04, 0.02);
  const auto n = slab.vertices.cols();
  Eigen::Matrix3Xd rest(3, 2 * n);
  rest << slab.vertices, slab.vertices.colwise() + Eigen::Vector3d(0.0, 0.0, 0.05);
  const Eigen::Matrix3Xi faces = boundary_triangles(slab.tetrahedra);
  Eigen::Matrix3Xi surface(3, 2 * faces.cols());
  surface << faces, faces.array() + static_cast<int>(n);
  const TriMesh probe = icosphere(1, 0.003);
  InstrumentContact contact(rest, surface, probe);
  // The lower slab turned inside out: mirrored through its bottom, every face facing in.
  Eigen::Matrix3Xd folded = rest;
  folded.leftCols(n).row(2) *= -1.0;
  const Eigen::Matrix3Xd still = Eigen::Matrix3Xd::Zero(3, folded.cols());
  constexpr double kDt = 0.01;
  // The probe 1 cm above the lower slab's bottom face, which faces down, toward the slab's
  // inside: "inside" the tissue by the test (the points on its top by more than this step's
  // motion can bring them, those on its bottom pushing it into the probe), outside it in fact.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.02, 0.02, 0.013);
  contact.resolve(pose, folded, still, kDt, still);  // the step before: the probe already there
  const std::vector<VertexTarget>& targets = contact.resolve(pose, folded, still, kDt, still);
  EXPECT_TRUE(targets.empty())
      << targets.size() << " tissue vertices moved, the first by "
      << (targets.front().target - folded.col(targets.front().vertex)).norm() << " m";
  EXPECT_FALSE(contact.refine(pose, folded, still));
  EXPECT_TRUE(contact.targets().empty());

  // The same probe against the slab as it is, 1 mm into its top: pushed.
  Eigen::Isometry3d pressing = Eigen::Isometry3d::Identity();
  pressing.translation() = Eigen::Vector3d(0.02, 0.02, 0.022);
  InstrumentContact intact(rest, surface, probe);
  intact.resolve(pressing, rest, still, kDt, still);
  EXPECT_FALSE(intact.resolve(pressing, rest, still, kDt, still).empty());
}

// A 4 x 4 x 2 cm slab of 5 mm cells (top at z = 2 cm) at rest, and a 6 mm probe.
class SlabAndProbe : public ::testing::Test {
 protected:
  static constexpr double kDt = 0.01;
  const MeshData slab = box_tets(8, 8, 4, 0.04, 0.04, 0.02);
  const Eigen::Matrix3Xi surface = boundary_triangles(slab.tetrahedra);
  const TriMesh probe = icosphere(1, 0.003);
  const Eigen::Matrix3Xd still = Eigen::Matrix3Xd::Zero(3, slab.vertices.cols());
};

// The contact's work follows the contact, not the tissue: with the probe out of reach nothing is
// refitted or searched, but "out of reach" counts the tissue's free flight, so tissue flying at
// a still probe within the step is caught, not passed through.
TEST_F(SlabAndProbe, SearchesOnlyWhenTheInstrumentIsWithinReachOfTheTissueOrItsFreeFlight) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.02, 0.02, 0.05);  // 2.7 cm above the top

  InstrumentContact contact(slab.vertices, surface, probe);
  EXPECT_TRUE(contact.resolve(pose, slab.vertices, still, kDt, still).empty());
  EXPECT_FALSE(contact.report().searched);
  EXPECT_EQ(contact.count_triangle_pairs(slab.vertices), 0);
  EXPECT_FALSE(contact.refine(pose, slab.vertices, still));

  // The slab rising at 4 m/s: 4 cm in the step, through the probe's 6 mm. Where the step starts
  // it is as far as before.
  Eigen::Matrix3Xd rising = still;
  rising.row(2).setConstant(4.0);
  EXPECT_FALSE(contact.resolve(pose, slab.vertices, rising, kDt, still).empty());
  EXPECT_TRUE(contact.report().searched);

  // Pressing 1 mm into the top: searched, and the step's trees know the tissue where it is.
  InstrumentContact pressed(slab.vertices, surface, probe);
  pose.translation().z() = 0.022;
  EXPECT_FALSE(pressed.resolve(pose, slab.vertices, still, kDt, still).empty());
  EXPECT_TRUE(pressed.report().searched);
  // The thesis's measure, taken after the step: the probe's triangles through the top's, in
  // the report, and the same when counted again (the count leaves the trees as it found them).
  const int pairs = pressed.count_triangle_pairs(slab.vertices);
  EXPECT_GT(pairs, 0);
  EXPECT_EQ(pressed.report().triangle_pairs, pairs);
  EXPECT_EQ(pressed.count_triangle_pairs(slab.vertices), pairs);
  // Withdrawn out of reach while holding: searched once more (the holds are let go), then not.
  pose.translation().z() = 0.05;
  pressed.resolve(pose, slab.vertices, still, kDt, still);
  EXPECT_TRUE(pressed.report().searched);
  EXPECT_TRUE(pressed.resolve(pose, slab.vertices, still, kDt, still).empty());
  EXPECT_FALSE(pressed.report().searched);
  EXPECT_EQ(pressed.measure(pose, slab.vertices).max_penetration, 0.0);
}

bool same_targets(const std::vector<VertexTarget>& a, const std::vector<VertexTarget>& b) {
  if (a.size() != b.size()) {
    return false;
  }
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].vertex != b[k].vertex || a[k].target != b[k].target || a[k].push != b[k].push
        || a[k].slides != b[k].slides) {
      return false;
    }
  }
  return true;
}

// Whether a step that ran out of contact passes had settled is asked of refine() without
// letting it act: the answer is refine()'s own, and the contact goes on exactly as one never
// asked (the same targets now, after the real correction and at the next step).
TEST_F(SlabAndProbe, AskingWhetherRefineWouldChangeChangesNothing) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.02, 0.02, 0.022);  // 1 mm into the top
  InstrumentContact asked(slab.vertices, surface, probe);
  InstrumentContact plain(slab.vertices, surface, probe);
  ASSERT_FALSE(asked.resolve(pose, slab.vertices, still, kDt, still).empty());
  plain.resolve(pose, slab.vertices, still, kDt, still);
  // The step "ended" with the tissue where it started, the probe's tip inside it, and a pulling
  // force on the first hold: the correction holds the triangles around the tip and drops it.
  Eigen::Matrix3Xd forces = still;
  forces.col(asked.targets().front().vertex) = -asked.targets().front().push;
  const std::vector<VertexTarget> before = asked.targets();
  EXPECT_TRUE(asked.refine_would_change(pose, slab.vertices, forces));
  EXPECT_TRUE(same_targets(asked.targets(), before));
  EXPECT_TRUE(asked.refine(pose, slab.vertices, forces));
  EXPECT_TRUE(plain.refine(pose, slab.vertices, forces));
  EXPECT_FALSE(same_targets(asked.targets(), before));
  EXPECT_TRUE(same_targets(asked.targets(), plain.targets()));
  // Asked again (the dropped hold's vertex is inside the probe: it may come back), answered
  // as refine() then acts; the next step is the same for both.
  const bool again = asked.refine_would_change(pose, slab.vertices, still);
  EXPECT_EQ(plain.refine(pose, slab.vertices, still), again);
  EXPECT_EQ(asked.refine(pose, slab.vertices, still), again);
  EXPECT_TRUE(same_targets(asked.targets(), plain.targets()));
  pose.translation().z() = 0.021;
  EXPECT_TRUE(same_targets(asked.resolve(pose, slab.vertices, still, kDt, still),
                           plain.resolve(pose, slab.vertices, still, kDt, still)));
}

}  // namespace
}  // namespace softbench::collision
