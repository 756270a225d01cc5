// SPDX-License-Identifier: MIT
#include "collision/instrument_contact.h"

#include "geometry/input_error.h"
#include "tests/collision/bvh_test_meshes.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace softbench::collision {
namespace {

using test::icosphere;
using ::testing::HasSubstr;

// A tool in millimetres beside tissue in metres is a thousand times larger than meant: sampled at
// the tissue's edge spacing it would take a million times the points. Refused with the limit,
// before any allocation, not run out of memory.
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
                 "InstrumentContact: the instrument mesh would take 27589242 contact points at the "
                 "tissue's edge spacing (0.001492 m), more than the limit of 2000000: is it in "
                 "other units than the tissue (millimetres beside metres)?");
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

}  // namespace
}  // namespace softbench::collision
