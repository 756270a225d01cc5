// SPDX-License-Identifier: MIT
#include "geometry/mesh_validation.h"

#include "geometry/input_error.h"
#include "geometry/mesh_measures.h"
#include "geometry/mesh_topology.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace softbench {
namespace {

using test::box_tets;
using test::cube_surface;
using test::single_tet;
using testing::AllOf;
using testing::Contains;
using testing::ElementsAre;
using testing::HasSubstr;
using testing::Not;
using testing::StartsWith;

using Severity = MeshProblem::Severity;

std::vector<std::string> messages(const ValidationReport& report) {
  std::vector<std::string> result;
  for (const MeshProblem& problem : report.problems) {
    result.push_back(problem.message);
  }
  return result;
}

int count_with(const ValidationReport& report, Severity severity) {
  return static_cast<int>(
      std::count_if(report.problems.begin(), report.problems.end(),
                    [&](const MeshProblem& p) { return p.severity == severity; }));
}

// The message of the InputError make_tet_mesh() throws, or "" if it builds the mesh.
std::string make_tet_mesh_error(const MeshData& data) {
  try {
    make_tet_mesh(data);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::string make_closed_surface_error(const MeshData& data) {
  try {
    make_closed_surface(data);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// The unit right tet with a fifth vertex that no tet uses.
MeshData single_tet_with_spare_vertex() {
  MeshData data = single_tet();
  data.vertices.conservativeResize(3, 5);
  data.vertices.col(4) << 2, 2, 2;
  return data;
}

// ---------------------------------------------------------------------------------------------
// Tets

TEST(ValidateTets, FindsNothingWrongWithAWellFormedBox) {
  const ValidationReport report = validate_tets(box_tets(3, 2, 2));

  EXPECT_TRUE(report.problems.empty()) << testing::PrintToString(messages(report));
  EXPECT_FALSE(report.has_errors());
  EXPECT_EQ(report.first_error("box"), "");
}

TEST(ValidateTets, NamesTheVertexWithANonFiniteCoordinate) {
  MeshData data = single_tet();
  data.vertices(0, 2) = std::numeric_limits<double>::quiet_NaN();
  const ValidationReport report = validate_tets(data);

  EXPECT_TRUE(report.has_errors());
  EXPECT_EQ(report.first_error("tet.msh"), "tet.msh: vertex 2: non-finite coordinate (nan, 1, 0)");
}

TEST(ValidateTets, NamesTheTetWithAVertexIndexOutOfRange) {
  MeshData data = single_tet();
  data.tetrahedra(3, 0) = 7;

  EXPECT_EQ(validate_tets(data).first_error("tet.msh"),
            "tet.msh: tet 0: vertex index 7 out of range (mesh has 4 vertices)");
}

TEST(ValidateTets, NamesTheTetWithARepeatedVertex) {
  MeshData data = single_tet();
  data.tetrahedra(2, 0) = 1;

  EXPECT_THAT(validate_tets(data).first_error("tet.msh"),
              HasSubstr("tet.msh: tet 0: repeated vertex 1"));
}

TEST(ValidateTets, RejectsATetOfFourCoplanarPoints) {
  MeshData data = single_tet();
  data.vertices.col(3) << 0.3, 0.3, 0.0;  // into the plane of the other three
  const ValidationReport report = validate_tets(data);

  EXPECT_TRUE(report.has_errors());
  EXPECT_THAT(report.first_error("tet.msh"),
              AllOf(StartsWith("tet.msh: tet 0: zero or near-zero volume (quality "),
                    HasSubstr("vertices 0 1 2 3")));
}

TEST(ValidateTets, RejectsANearlyFlatTetButAcceptsAThinOne) {
  // Quality ~ height / edge: 1e-9 is round-off-level flatness, 1e-3 a poor but real element.
  MeshData flat = single_tet();
  flat.vertices(2, 3) = 1e-9;
  MeshData thin = single_tet();
  thin.vertices(2, 3) = 1e-3;

  EXPECT_TRUE(validate_tets(flat).has_errors());
  EXPECT_FALSE(validate_tets(thin).has_errors());
}

TEST(ValidateTets, WarnsAboutAnInvertedTetWithoutChangingIt) {
  MeshData data = single_tet();
  std::swap(data.tetrahedra(1, 0), data.tetrahedra(2, 0));
  const ValidationReport report = validate_tets(data);

  EXPECT_FALSE(report.has_errors());
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_EQ(report.problems[0].severity, Severity::kWarning);
  EXPECT_THAT(report.problems[0].message, StartsWith("tet 0: inverted (negative volume -0.17)"));
  EXPECT_EQ(report.reoriented_tets, 0);
}

TEST(ValidateTets, WarnsAboutAVertexNoTetUses) {
  const ValidationReport report = validate_tets(single_tet_with_spare_vertex());

  EXPECT_FALSE(report.has_errors());
  EXPECT_THAT(messages(report), ElementsAre("vertex 4: used by no tetrahedron"));
}

TEST(ValidateTets, ListsTheFirstTenOfAKindAndCountsTheRest) {
  MeshData data = box_tets(10, 10, 10);  // 6000 tets
  data.tetrahedra.row(1).swap(data.tetrahedra.row(2));
  const ValidationReport report = validate_tets(data);

  ASSERT_EQ(report.problems.size(), 11u);
  EXPECT_THAT(report.problems[0].message, StartsWith("tet 0: inverted"));
  EXPECT_THAT(report.problems[9].message, StartsWith("tet 9: inverted"));
  EXPECT_EQ(report.problems[10].message, "... and 5990 more inverted tets");
  EXPECT_EQ(report.problems[10].severity, Severity::kWarning);
}

TEST(ValidateTets, CapsEachKindSeparately) {
  MeshData data = box_tets(4, 4, 4);  // 384 tets, 125 vertices
  data.tetrahedra.row(1).swap(data.tetrahedra.row(2));
  data.tetrahedra.rightCols<20>().row(0).setConstant(1000);
  const ValidationReport report = validate_tets(data);

  const std::vector<std::string> all = messages(report);
  EXPECT_THAT(all, Contains("... and 354 more inverted tets"));
  EXPECT_THAT(all, Contains("... and 10 more tets with out-of-range vertex indices"));
  EXPECT_EQ(count_with(report, Severity::kError), 11);
  EXPECT_THAT(report.first_error("box.msh"),
              StartsWith("box.msh: tet 364: vertex index 1000 out of range (mesh has 125 "));
}

TEST(ValidateTets, RequiresAtLeastOneTet) {
  EXPECT_EQ(validate_tets(cube_surface()).first_error("cube.obj"), "cube.obj: no tetrahedra");
}

// ---------------------------------------------------------------------------------------------
// make_tet_mesh

TEST(MakeTetMesh, KeepsAWellFormedMeshAsItIs) {
  const MeshData data = box_tets(3, 2, 2, 2.0, 1.0, 1.0);
  ValidationReport report;
  const TetMesh mesh = make_tet_mesh(data, &report);

  EXPECT_TRUE(report.problems.empty());
  EXPECT_EQ(mesh.rest_positions(), data.vertices);
  EXPECT_EQ(mesh.tets(), data.tetrahedra);
  EXPECT_NEAR(mesh_volume(mesh), 2.0, test::kRoundoff);
}

TEST(MakeTetMesh, ReorientsInvertedTetsAndCountsThem) {
  MeshData data = box_tets(2, 2, 2);
  for (Eigen::Index t = 0; t < data.tetrahedra.cols(); t += 3) {
    std::swap(data.tetrahedra(0, t), data.tetrahedra(3, t));
  }
  ValidationReport report;
  const TetMesh mesh = make_tet_mesh(data, &report);

  EXPECT_EQ(report.reoriented_tets, 48 / 3);
  EXPECT_FALSE(report.has_errors());
  EXPECT_THAT(report.problems.at(0).message, HasSubstr("inverted"));
  EXPECT_THAT(report.problems.at(0).message, HasSubstr("; reoriented"));
  const Eigen::Matrix3Xd& x = mesh.rest_positions();
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const auto tet = mesh.tets().col(t);
    EXPECT_GT(signed_tet_volume(x.col(tet(0)), x.col(tet(1)), x.col(tet(2)), x.col(tet(3))), 0.0)
        << "tet " << t;
  }
  EXPECT_NEAR(mesh_volume(mesh), 1.0, test::kRoundoff);
}

TEST(MakeTetMesh, ThrowsOnEveryErrorNamingTheSourceAndTheElement) {
  struct Case {
    const char* name;
    MeshData data;
    const char* expected;
  };
  std::vector<Case> cases;
  {
    MeshData data = single_tet();
    data.vertices(1, 0) = std::numeric_limits<double>::infinity();
    cases.push_back(
        {"non-finite", data, "single_tet: vertex 0: non-finite coordinate (0, inf, 0)"});
  }
  {
    MeshData data = single_tet();
    data.tetrahedra(0, 0) = -1;
    cases.push_back({"negative index", data, "single_tet: tet 0: vertex index -1 out of range"});
  }
  {
    MeshData data = single_tet();
    data.tetrahedra(3, 0) = 0;
    cases.push_back({"repeated", data, "single_tet: tet 0: repeated vertex 0"});
  }
  {
    MeshData data = single_tet();
    data.vertices.col(3) << 1, 1, 0;
    cases.push_back({"coplanar", data, "single_tet: tet 0: zero or near-zero volume"});
  }
  cases.push_back(
      {"unreferenced", single_tet_with_spare_vertex(), "single_tet: vertex 4: used by no tet"});
  {
    MeshData data = single_tet();
    data.tetrahedra.resize(4, 0);
    cases.push_back({"no tets", data, "single_tet: no tetrahedra"});
  }

  for (const Case& c : cases) {
    EXPECT_THAT(make_tet_mesh_error(c.data), StartsWith(c.expected)) << c.name;
  }
}

TEST(MakeTetMesh, DoesNotClaimToReorientTetsOfAMeshItRejects) {
  MeshData data = single_tet_with_spare_vertex();
  std::swap(data.tetrahedra(1, 0), data.tetrahedra(2, 0));
  ValidationReport report;
  EXPECT_THROW(make_tet_mesh(data, &report), InputError);

  EXPECT_EQ(report.reoriented_tets, 0);
  EXPECT_THAT(messages(report), Contains(StartsWith("tet 0: inverted")));
  EXPECT_THAT(messages(report), Not(Contains(HasSubstr("reoriented"))));
}

TEST(MakeTetMesh, FillsTheReportBeforeThrowing) {
  ValidationReport report;
  EXPECT_THROW(make_tet_mesh(single_tet_with_spare_vertex(), &report), InputError);

  EXPECT_TRUE(report.has_errors());
  EXPECT_THAT(messages(report), ElementsAre("vertex 4: used by no tetrahedron"));
}

// ---------------------------------------------------------------------------------------------
// Surfaces

MeshData cube_missing_a_triangle() {
  MeshData data = cube_surface();
  data.triangles.conservativeResize(3, 11);
  return data;
}

MeshData cube_with_a_flipped_triangle() {
  MeshData data = cube_surface();
  std::swap(data.triangles(1, 5), data.triangles(2, 5));
  return data;
}

// Three triangles hinged on the edge 0-1, like pages of a book.
MeshData three_pages() {
  MeshData data;
  data.vertices.resize(3, 5);
  data.vertices << 0, 1, 0, 0, 0.5,  //
      0, 0, 1, -1, 0,                //
      0, 0, 0, 0, 1;
  data.triangles.resize(3, 3);
  data.triangles << 0, 1, 0,  //
      1, 0, 1,                //
      2, 3, 4;
  data.source = "pages.obj";
  return data;
}

TEST(ValidateSurface, FindsNothingWrongWithTheClosedCube) {
  const ValidationReport report = validate_surface(cube_surface(), /*require_closed=*/true);

  EXPECT_TRUE(report.problems.empty()) << testing::PrintToString(messages(report));
}

TEST(ValidateSurface, ReportsOpenEdgesAsErrorsOnlyWhenClosedIsRequired) {
  const ValidationReport closed = validate_surface(cube_missing_a_triangle(), true);
  const ValidationReport open = validate_surface(cube_missing_a_triangle(), false);

  EXPECT_THAT(closed.first_error("cube.obj"),
              StartsWith("cube.obj: surface: 3 open (boundary) edges, e.g. "));
  EXPECT_FALSE(open.has_errors());
  EXPECT_THAT(messages(open), ElementsAre(StartsWith("surface: 3 open (boundary) edges")));
}

TEST(ValidateSurface, ReportsAnEdgeSharedByThreeTriangles) {
  const ValidationReport report = validate_surface(three_pages(), true);

  EXPECT_TRUE(report.has_errors());
  EXPECT_THAT(messages(report),
              Contains(AllOf(StartsWith("surface: 1 non-manifold edge"), HasSubstr("e.g. 0-1"))));
}

TEST(ValidateSurface, ReportsATriangleFacingTheWrongWay) {
  const ValidationReport report = validate_surface(cube_with_a_flipped_triangle(), true);

  EXPECT_TRUE(report.has_errors());
  EXPECT_THAT(messages(report),
              ElementsAre(StartsWith("surface: 3 inconsistently oriented edges")));
}

TEST(ValidateSurface, WarnsAboutZeroAreaRepeatedVertexAndUnusedVertices) {
  MeshData data = cube_surface();
  data.vertices.conservativeResize(3, 10);
  data.vertices.col(8) << 0.5, 0.5, 0.0;  // on the diagonal 0-3 of the bottom face
  data.vertices.col(9) << 7, 7, 7;        // used by nothing
  data.triangles.conservativeResize(3, 14);
  data.triangles.col(12) << 0, 8, 3;  // collinear
  data.triangles.col(13) << 4, 4, 5;  // a segment
  const ValidationReport report = validate_surface(data, /*require_closed=*/false);

  EXPECT_EQ(count_with(report, Severity::kError), 0);
  EXPECT_THAT(messages(report), Contains(StartsWith("triangle 12: zero or near-zero area")));
  EXPECT_THAT(messages(report), Contains("triangle 13: repeated vertex 4"));
  EXPECT_THAT(messages(report), Contains("vertex 9: used by no triangle"));
}

TEST(ValidateSurface, RejectsNonFiniteCoordinatesAndIndicesOutOfRange) {
  MeshData nan = cube_surface();
  nan.vertices(2, 7) = -std::numeric_limits<double>::infinity();
  MeshData out_of_range = cube_surface();
  out_of_range.triangles(1, 4) = 8;

  EXPECT_EQ(validate_surface(nan, false).first_error("c"),
            "c: vertex 7: non-finite coordinate (1, 1, -inf)");
  EXPECT_EQ(validate_surface(out_of_range, false).first_error("c"),
            "c: triangle 4: vertex index 8 out of range (mesh has 8 vertices)");
}

// ---------------------------------------------------------------------------------------------
// make_closed_surface

TEST(MakeClosedSurface, TurnsAnInsideOutSurfaceOutward) {
  MeshData data = cube_surface();
  data.triangles.row(1).swap(data.triangles.row(2));
  const TriMesh surface = make_closed_surface(data);

  EXPECT_EQ(surface.num_triangles(), 12);
  EXPECT_NEAR(enclosed_volume(surface), 1.0, test::kRoundoff);
}

TEST(MakeClosedSurface, DropsVerticesNoTriangleUses) {
  MeshData data = cube_surface();
  data.vertices.conservativeResize(3, 9);
  data.vertices.col(8) = data.vertices.col(0);
  data.vertices.col(0) << 5, 5, 5;
  data.triangles = data.triangles.unaryExpr([](int v) { return v == 0 ? 8 : v; }).eval();
  const TriMesh surface = make_closed_surface(data);

  EXPECT_EQ(surface.num_vertices(), 8);
  EXPECT_NEAR(enclosed_volume(surface), 1.0, test::kRoundoff);
  EXPECT_TRUE(surface_topology(surface.triangles, surface.num_vertices()).closed_manifold());
}

TEST(MakeClosedSurface, ThrowsNamingTheSourceForOpenNonManifoldOrMisorientedSurfaces) {
  EXPECT_THAT(make_closed_surface_error(cube_missing_a_triangle()),
              StartsWith("cube_surface: surface: 3 open"));
  EXPECT_THAT(make_closed_surface_error(three_pages()), StartsWith("pages.obj: surface: "));
  EXPECT_THAT(make_closed_surface_error(cube_with_a_flipped_triangle()),
              StartsWith("cube_surface: surface: 3 inconsistently oriented edges"));
}

TEST(MakeClosedSurface, RejectsASurfaceThatEnclosesNothing) {
  // Two triangles back to back: closed and consistently oriented, but flat.
  MeshData data;
  data.vertices.resize(3, 3);
  data.vertices << 0, 1, 0,  //
      0, 0, 1,               //
      0, 0, 0;
  data.triangles.resize(3, 2);
  data.triangles << 0, 0,  //
      1, 2,                //
      2, 1;
  data.source = "sheet.obj";

  EXPECT_THAT(make_closed_surface_error(data),
              StartsWith("sheet.obj: surface: encloses no volume"));
}

}  // namespace
}  // namespace softbench
