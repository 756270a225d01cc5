// SPDX-License-Identifier: MIT
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/text_tokenizer.h"
#include "tests/geometry/mesh_file_test_support.h"
#include "tests/test_meshes.h"
#include "tests/test_tolerances.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <iterator>
#include <numbers>
#include <stdexcept>
#include <string>

namespace softbench {
namespace {

using test::box_tets;
using test::cube_surface;
using test::TempDir;
using test::ThrowsInputError;
using testing::HasSubstr;

void expect_same_mesh(const MeshData& read, const MeshData& written) {
  ASSERT_EQ(read.vertices.cols(), written.vertices.cols());
  ASSERT_EQ(read.triangles.cols(), written.triangles.cols());
  ASSERT_EQ(read.tetrahedra.cols(), written.tetrahedra.cols());
  EXPECT_EQ(read.triangles, written.triangles);
  EXPECT_EQ(read.tetrahedra, written.tetrahedra);
  if (written.vertices.size() > 0) {
    EXPECT_LE((read.vertices - written.vertices).cwiseAbs().maxCoeff(), test::kTextRoundTrip);
  }
}

// A box of tets with some boundary-like triangles too, in a box whose sides are not round
// numbers in binary.
MeshData tets_and_triangles() {
  MeshData mesh = box_tets(3, 2, 2, 1.5, 0.7, 0.3);
  mesh.triangles.resize(3, 5);
  for (Eigen::Index t = 0; t < 5; ++t) {
    mesh.triangles.col(t) = mesh.tetrahedra.col(t).head<3>();
  }
  return mesh;
}

TEST(MeshRoundTrip, ObjKeepsTheCubeSurface) {
  TempDir dir;
  const MeshData cube = cube_surface();
  write_obj(dir.path() / "cube.obj", cube);
  expect_same_mesh(read_obj(dir.path() / "cube.obj"), cube);
}

TEST(MeshRoundTrip, MshKeepsTetsAndTriangles) {
  TempDir dir;
  const MeshData mesh = tets_and_triangles();
  write_msh(dir.path() / "box.msh", mesh);
  EXPECT_THAT(read_file_bytes(dir.path() / "box.msh"), HasSubstr("$MeshFormat\n2.2 0 8\n"));
  expect_same_mesh(read_msh(dir.path() / "box.msh"), mesh);
}

TEST(MeshRoundTrip, VtuKeepsTetsAndTrianglesAndWritesVertexFields) {
  TempDir dir;
  const MeshData mesh = tets_and_triangles();
  const Eigen::Matrix3Xd displacement = 0.01 * mesh.vertices;
  const VertexField fields[] = {{"displacement <mm>", &displacement}};
  write_vtu(dir.path() / "box.vtu", mesh, fields);
  const std::string text = read_file_bytes(dir.path() / "box.vtu");
  EXPECT_THAT(text, HasSubstr("Name=\"displacement &lt;mm&gt;\" NumberOfComponents=\"3\""));
  EXPECT_THAT(text, HasSubstr("<PointData>"));
  expect_same_mesh(read_vtu(dir.path() / "box.vtu"), mesh);
}

TEST(MeshRoundTrip, TetgenKeepsTetsAndTriangles) {
  TempDir dir;
  const MeshData mesh = tets_and_triangles();
  write_tetgen(dir.path() / "box", mesh);
  expect_same_mesh(read_tetgen(dir.path() / "box"), mesh);
}

TEST(MeshRoundTrip, EveryWriterKeepsAwkwardCoordinatesBitForBit) {
  TempDir dir;
  MeshData mesh = test::single_tet();
  mesh.vertices << 0.1, 1.0 / 3.0, -2.5e17, std::numbers::pi,  //
      1e-300, 5e-324, -0.0, 123456789.123456789,               //
      std::nextafter(1.0, 2.0), 2.0 / 3.0, 1e22, -7.0 / 9.0;
  mesh.triangles = mesh.tetrahedra.topRows<3>();
  const std::function<MeshData()> round_trips[] = {
      [&] {
        write_obj(dir.path() / "t.obj", mesh);
        return read_obj(dir.path() / "t.obj");
      },
      [&] {
        write_msh(dir.path() / "t.msh", mesh);
        return read_msh(dir.path() / "t.msh");
      },
      [&] {
        write_vtu(dir.path() / "t.vtu", mesh);
        return read_vtu(dir.path() / "t.vtu");
      },
      [&] {
        write_tetgen(dir.path() / "t", mesh);
        return read_tetgen(dir.path() / "t");
      },
  };
  for (const auto& round_trip : round_trips) {
    const MeshData read = round_trip();
    ASSERT_EQ(read.vertices.cols(), mesh.vertices.cols()) << read.source;
    for (Eigen::Index i = 0; i < mesh.vertices.size(); ++i) {
      EXPECT_EQ(read.vertices(i), mesh.vertices(i)) << read.source << " value " << i;
    }
  }
}

TEST(WriteTetgen, RemovesAStaleEleFileWhenTheMeshHasNoTets) {
  TempDir dir;
  write_tetgen(dir.path() / "m", tets_and_triangles());
  write_tetgen(dir.path() / "m", cube_surface());
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "m.ele"));
  expect_same_mesh(read_tetgen(dir.path() / "m"), cube_surface());
}

TEST(WriteObj, ReportsAPathThatCannotBeWritten) {
  TempDir dir;
  EXPECT_THAT([&] { write_obj(dir.path() / "missing" / "x.obj", cube_surface()); },
              ThrowsInputError("x.obj: cannot write (No such file or directory)"));
}

TEST(WriteObj, ReplacesAnExistingFileAndLeavesNoTemporaryBehind) {
  TempDir dir;
  dir.write("cube.obj", "previous content\n");
  write_obj(dir.path() / "cube.obj", cube_surface());
  expect_same_mesh(read_obj(dir.path() / "cube.obj"), cube_surface());
  const auto entries = std::distance(std::filesystem::directory_iterator(dir.path()),
                                     std::filesystem::directory_iterator());
  EXPECT_EQ(entries, 1);
}

TEST(WriteVtu, RejectsAFieldOfTheWrongSize) {
  TempDir dir;
  const Eigen::Matrix3Xd too_short = Eigen::Matrix3Xd::Zero(3, 2);
  const VertexField fields[] = {{"velocity", &too_short}};
  EXPECT_THROW(write_vtu(dir.path() / "bad.vtu", cube_surface(), fields), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "bad.vtu"));
}

TEST(ReadMesh, DispatchesOnTheExtensionIgnoringCase) {
  TempDir dir;
  const MeshData cube = cube_surface();
  write_obj(dir.path() / "a.OBJ", cube);
  write_msh(dir.path() / "b.Msh", cube);
  write_vtu(dir.path() / "c.vtu", cube);
  write_tetgen(dir.path() / "d", cube);
  const auto vtk = dir.write("e.vtk",
                             "# vtk DataFile Version 3.0\ncube\nASCII\nDATASET POLYDATA\n"
                             "POINTS 3 double\n0 0 0 1 0 0 0 1 0\nPOLYGONS 1 4\n3 0 1 2\n");
  const auto stl = dir.write("f.STL",
                             "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                             "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n");
  for (const char* name : {"a.OBJ", "b.Msh", "c.vtu", "d.node", "d.face"}) {
    expect_same_mesh(read_mesh(dir.path() / name), cube);
  }
  EXPECT_EQ(read_mesh(vtk).triangles.cols(), 1);
  EXPECT_EQ(read_mesh(stl).triangles.cols(), 1);
}

TEST(ReadMesh, RejectsUnknownExtensions) {
  TempDir dir;
  const auto spheres = dir.write("liver.sph", "sph 1.0\nnums 1\nsphere 0 0 0 0.85\n");
  const auto material = dir.write("liver.mtl", "newmtl mat1\nKd 1 0 0\n");
  const auto bare = dir.write("liver", "v 0 0 0\n");
  EXPECT_THAT([&] { read_mesh(spheres); },
              ThrowsInputError("liver.sph: unknown mesh file extension '.sph' (expected .obj, "
                               ".msh, .node, .ele, .face, .stl, .vtk or .vtu)"));
  EXPECT_THAT([&] { read_mesh(material); },
              ThrowsInputError("liver.mtl: unknown mesh file extension '.mtl' (expected .obj, "
                               ".msh, .node, .ele, .face, .stl, .vtk or .vtu)"));
  EXPECT_THAT([&] { read_mesh(bare); }, ThrowsInputError("liver: no file extension (expected .obj, "
                                                         ".msh, .node, .ele, .face, .stl, .vtk or "
                                                         ".vtu)"));
}

TEST(ReadMesh, RejectsContentThatDoesNotMatchTheExtension) {
  TempDir dir;
  const auto path = dir.write("surface.msh", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_THAT([&] { read_mesh(path); },
              ThrowsInputError("surface.msh: line 1: expected $MeshFormat (MSH 2.2, 4.1) or $NOD "
                               "(MSH 1) at the start of a Gmsh file, found 'v'"));
}

}  // namespace
}  // namespace softbench
