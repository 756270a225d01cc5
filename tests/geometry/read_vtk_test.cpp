// SPDX-License-Identifier: MIT
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "tests/geometry/mesh_file_test_support.h"
#include "tests/test_meshes.h"

#include <limits>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>
#include <string>

namespace softbench {
namespace {

using test::ByteWriter;
using test::random_bytes;
using test::TempDir;
using test::ThrowsInputError;

constexpr const char* kPolydataHeader =
    "# vtk DataFile Version 3.0\nsurface\nASCII\nDATASET POLYDATA\n";

// A unit square and the apex of a pyramid over it.
constexpr const char* kFivePoints =
    "POINTS 5 float\n"
    "0 0 0  1 0 0  1 1 0\n"
    "0 1 0  0.5 0.5 1\n";

TEST(ReadVtk, ReadsAsciiPolydataFanTriangulatingPolygons) {
  TempDir dir;
  const auto path = dir.write("pyramid.vtk", std::string(kPolydataHeader) + kFivePoints +
                                                 "VERTICES 1 2\n1 4\n"
                                                 "LINES 1 3\n2 0 4\n"
                                                 "POLYGONS 3 13\n"
                                                 "4 0 3 2 1\n"
                                                 "3 0 1 4\n"
                                                 "3 1 2 4\n"
                                                 "POINT_DATA 5\nSCALARS s float 1\n"
                                                 "LOOKUP_TABLE default\n0 1 2 3 4\n");
  const MeshData mesh = read_vtk(path);
  ASSERT_EQ(mesh.vertices.cols(), 5);
  ASSERT_EQ(mesh.triangles.cols(), 4);
  EXPECT_EQ(mesh.vertices.col(4), Eigen::Vector3d(0.5, 0.5, 1));
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 3, 2));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(0, 2, 1));
  EXPECT_EQ(mesh.triangles.col(3), Eigen::Vector3i(1, 2, 4));
}

TEST(ReadVtk, TriangulatesTriangleStripsKeepingTheirOrientation) {
  TempDir dir;
  const auto path = dir.write(
      "strip.vtk", std::string(kPolydataHeader) + kFivePoints + "TRIANGLE_STRIPS 1 5\n4 0 1 3 2\n");
  const MeshData mesh = read_vtk(path);
  ASSERT_EQ(mesh.triangles.cols(), 2);
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 1, 3));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(3, 1, 2));
}

TEST(ReadVtk, ReadsUnstructuredGridKeepingTrianglesAndTetsOnly) {
  TempDir dir;
  const auto path = dir.write("grid.vtk",
                              "# vtk DataFile Version 2.0\n"
                              "\n"  // an empty title is allowed
                              "ASCII\n"
                              "DATASET UNSTRUCTURED_GRID\n"
                              "FIELD FieldData 1\nTIME 1 1 double\n0.5\n" +
                                  std::string(kFivePoints) +
                                  "CELLS 6 25\n"
                                  "1 4\n"
                                  "2 0 4\n"
                                  "4 0 1 2 3\n"
                                  "3 0 1 4\n"
                                  "4 0 1 3 4\n"
                                  "5 0 1 2 3 4\n"
                                  "CELL_TYPES 6\n1 3 9 5 10 14\n"
                                  "CELL_DATA 6\nSCALARS id int 1\nLOOKUP_TABLE default\n"
                                  "0 1 2 3 4 5\n");
  const MeshData mesh = read_vtk(path);
  ASSERT_EQ(mesh.triangles.cols(), 1);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 1, 4));
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 3, 4));
}

TEST(ReadVtk, ReadsVersion51OffsetsAndConnectivity) {
  TempDir dir;
  const auto path = dir.write("v51.vtk",
                              "# vtk DataFile Version 5.1\nvtk output\nASCII\n"
                              "DATASET UNSTRUCTURED_GRID\n" +
                                  std::string(kFivePoints) +
                                  "METADATA\nINFORMATION 0\n\n"
                                  "CELLS 3 7\n"
                                  "OFFSETS vtktypeint64\n0 4 7\n"
                                  "CONNECTIVITY vtktypeint64\n0 1 3 4 1 2 4\n"
                                  "CELL_TYPES 2\n10\n5\n");
  const MeshData mesh = read_vtk(path);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  ASSERT_EQ(mesh.triangles.cols(), 1);
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 3, 4));
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(1, 2, 4));
}

// Legacy binary VTK stores every number big-endian, right after its keyword line.
std::string binary_polydata(std::uint32_t claimed_points) {
  ByteWriter out(std::endian::big);
  out.text("# vtk DataFile Version 3.0\nvtk output\nBINARY\nDATASET POLYDATA\n");
  out.text("POINTS " + std::to_string(claimed_points) + " float\n");
  for (float value : {0.f, 0.f, 0.f, 2.5f, 0.f, 0.f, 0.f, -1.25f, 0.f, 0.f, 0.f, 10.f}) {
    out.put(value);
  }
  out.text("\nPOLYGONS 2 8\n");
  for (std::int32_t value : {3, 0, 2, 1, 3, 0, 1, 3}) {
    out.put(value);
  }
  out.text("\n");
  return out.bytes();
}

TEST(ReadVtk, ReadsBinaryBigEndianPolydata) {
  TempDir dir;
  const MeshData mesh = read_vtk(dir.write("binary.vtk", binary_polydata(4)));
  ASSERT_EQ(mesh.vertices.cols(), 4);
  ASSERT_EQ(mesh.triangles.cols(), 2);
  EXPECT_EQ(mesh.vertices.col(1), Eigen::Vector3d(2.5, 0, 0));
  EXPECT_EQ(mesh.vertices.col(2), Eigen::Vector3d(0, -1.25, 0));
  EXPECT_EQ(mesh.vertices.col(3), Eigen::Vector3d(0, 0, 10));
  EXPECT_EQ(mesh.triangles.col(0), Eigen::Vector3i(0, 2, 1));
  EXPECT_EQ(mesh.triangles.col(1), Eigen::Vector3i(0, 1, 3));
}

TEST(ReadVtk, ReadsBinaryVersion51UnstructuredGridWithDoubles) {
  TempDir dir;
  ByteWriter out(std::endian::big);
  out.text("# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET UNSTRUCTURED_GRID\n");
  out.text("POINTS 4 double\n");
  for (double value : {0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0 / 3.0}) {
    out.put(value);
  }
  out.text("\nCELLS 2 4\nOFFSETS vtktypeint64\n");
  out.put(std::int64_t{0}).put(std::int64_t{4});
  out.text("\nCONNECTIVITY vtktypeint64\n");
  for (std::int64_t value : {0, 1, 2, 3}) {
    out.put(value);
  }
  out.text("\nCELL_TYPES 1\n");
  out.put(std::int32_t{10});
  out.text("\n");
  const MeshData mesh = read_vtk(dir.write("binary51.vtk", out.bytes()));
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
  EXPECT_EQ(mesh.vertices(0, 0), 0.1);
  EXPECT_EQ(mesh.vertices(2, 3), 1.0 / 3.0);
}

// A 5.1 grid whose connectivity is stored as doubles: whole numbers read as indices.
std::string binary51_with_double_connectivity(double third_index) {
  ByteWriter out(std::endian::big);
  out.text("# vtk DataFile Version 5.1\nvtk output\nBINARY\nDATASET UNSTRUCTURED_GRID\n");
  out.text("POINTS 4 double\n");
  for (double value : {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) {
    out.put(value);
  }
  out.text("\nCELLS 2 4\nOFFSETS double\n");
  out.put(0.0).put(4.0);
  out.text("\nCONNECTIVITY double\n");
  for (double value : {0.0, 1.0, third_index, 3.0}) {
    out.put(value);
  }
  out.text("\nCELL_TYPES 1\n");
  out.put(std::int32_t{10});
  out.text("\n");
  return out.bytes();
}

TEST(ReadVtk, ReadsWholeNumberIndicesStoredAsDoublesAndRejectsOthers) {
  TempDir dir;
  const MeshData mesh = read_vtk(dir.write("whole.vtk", binary51_with_double_connectivity(2.0)));
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
  // 0.7 is no vertex (truncating it to 0 made a degenerate tet); a NaN has no integer value.
  const auto fraction = dir.write("fraction.vtk", binary51_with_double_connectivity(0.7));
  EXPECT_THAT([&] { read_vtk(fraction); }, ThrowsInputError("fraction.vtk: line 11: CELLS "
                                                            "CONNECTIVITY: value 0.7 is not a "
                                                            "whole number"));
  const auto nan = dir.write(
      "nan.vtk", binary51_with_double_connectivity(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_THAT([&] { read_vtk(nan); }, ThrowsInputError("nan.vtk: line 11: CELLS CONNECTIVITY: "
                                                       "value nan is not a whole number"));
}

TEST(ReadVtk, RejectsABinaryFieldWhoseSizeWrapsAround) {
  TempDir dir;
  // 2147437309 components x 1073764994 tuples of doubles is 2^64 + 537552 bytes: multiplied in
  // 64 bits it wrapped to 537552, and with that much data behind it the array was skipped as if
  // the file held it.
  ByteWriter out(std::endian::big);
  out.text(std::string("# vtk DataFile Version 3.0\nvtk output\nBINARY\nDATASET POLYDATA\n")
           + "FIELD FieldData 1\nHUGE 2147437309 1073764994 double\n");
  out.text(std::string(537552, '\0'));
  out.text("\n");
  const auto path = dir.write("wrap.vtk", out.bytes());
  EXPECT_THAT([&] { read_vtk(path); }, ThrowsInputError("wrap.vtk: line 6: truncated: values of "
                                                        "field array 'HUGE' needs "
                                                        "2305843009213761146 x 8 bytes of binary "
                                                        "data, only 537553 remain"));
}

TEST(ReadVtk, RejectsBinaryWithTooFewBytes) {
  TempDir dir;
  const auto path = dir.write("short.vtk",
                              "# vtk DataFile Version 3.0\nvtk output\nBINARY\nDATASET POLYDATA\n"
                              "POINTS 8 float\n"
                                  + random_bytes(19, 20));
  EXPECT_THAT(
      [&] { read_vtk(path); },
      ThrowsInputError("short.vtk: line 5: truncated: POINTS needs 96 bytes of binary data, "
                       "only 20 remain"));
}

TEST(ReadVtk, RejectsBinaryPointsCountThatDisagreesWithTheData) {
  TempDir dir;
  // Claims 5 points while 4 are stored: the polygon keyword is swallowed as coordinates.
  const auto path = dir.write("count.vtk", binary_polydata(5));
  EXPECT_THAT([&] { read_vtk(path); }, ThrowsInputError("count.vtk: line 7: unexpected keyword '8' "
                                                        "in a POLYDATA dataset"));
}

TEST(ReadVtk, RejectsPointIndexOutOfRange) {
  TempDir dir;
  const auto path = dir.write(
      "range.vtk", std::string(kPolydataHeader) + kFivePoints + "POLYGONS 1 4\n3 0 1 5\n");
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("range.vtk: line 8: POLYGONS: cell 0: point index 5 out of range "
                               "(file has 5 points)"));
}

TEST(ReadVtk, RejectsUnknownCellType) {
  TempDir dir;
  const auto path = dir.write(
      "type.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                      + std::string(kFivePoints) + "CELLS 1 5\n4 0 1 2 4\nCELL_TYPES 1\n99\n");
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("type.vtk: line 10: cell 0 has unknown cell type 99"));
}

TEST(ReadVtk, RejectsTetCellWithTheWrongNumberOfPoints) {
  TempDir dir;
  const auto path = dir.write(
      "tet.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                     + std::string(kFivePoints) + "CELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n10\n");
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("tet.vtk: line 10: cell 0 has 3 points; type 10 (tetra) needs 4"));
}

TEST(ReadVtk, RejectsNanCoordinate) {
  TempDir dir;
  const auto path =
      dir.write("nan.vtk", std::string(kPolydataHeader) + "POINTS 2 double\n0 0 0\n1 nan 0\n");
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("nan.vtk: line 7: point 1 has a non-finite coordinate (nan)"));
}

TEST(ReadVtk, RejectsCellListThatDisagreesWithItsCount) {
  TempDir dir;
  const auto path = dir.write(
      "cells.vtk", std::string(kPolydataHeader) + kFivePoints + "POLYGONS 2 4\n3 0 1 4\n");
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("cells.vtk: line 8: POLYGONS: header says 2 cells, the cell list "
                               "holds 1"));
}

TEST(ReadVtk, RejectsTruncatedAsciiPoints) {
  TempDir dir;
  const auto path =
      dir.write("cut.vtk", std::string(kPolydataHeader) + "POINTS 3 float\n0 0 0 1 0");
  EXPECT_THAT(
      [&] { read_vtk(path); },
      ThrowsInputError("cut.vtk: line 6: expected 9 values of POINTS, found 5 before end of "
                       "file"));
}

TEST(ReadVtk, RejectsUnsupportedDatasets) {
  TempDir dir;
  const auto path = dir.write(
      "image.vtk", "# vtk DataFile Version 3.0\nimage\nASCII\nDATASET STRUCTURED_POINTS\n");
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("image.vtk: line 4: unsupported dataset 'STRUCTURED_POINTS' "
                               "(expected POLYDATA or UNSTRUCTURED_GRID)"));
}

TEST(ReadVtk, RejectsRandomBytes) {
  TempDir dir;
  const auto path = dir.write("noise.vtk", random_bytes(23, 4096));
  EXPECT_THAT([&] { read_vtk(path); },
              ThrowsInputError("noise.vtk: line 1: expected '# vtk DataFile Version x.y' as the "
                               "first line of a legacy VTK file, found "
                               "'\\x84\\xab\\xf2/\\xc3\\xc8H\\x928q\\xaf/*\\x19d8\\x9e\\xd5im\\x00"
                               "\\xc1\\xe2\\xff\\xe2\\x00L\\xf9\\x96k\\xfa\\xae\\xd8\\xc0\\x10\\x94"
                               "KeIz...'"));
}

TEST(ReadVtk, RejectsHeaderFollowedByRandomBytes) {
  TempDir dir;
  const auto path = dir.write(
      "garbage.vtk", std::string(kPolydataHeader) + "POINTS 3 float\n" + random_bytes(29, 4096));
  EXPECT_THAT([&] { read_vtk(path); }, ThrowsInputError("garbage.vtk: line 6: point 0 has a "
                                                        "coordinate that is not a number "
                                                        "('\\xdd\\xccHX\\x12\\xf8\\xc3}sU\\x8aT\\xb"
                                                        "a\\xda\\xd9\\xd4\\xc4\\xab\\xbb\\xd7=!\\xb"
                                                        "8,\\x0eZh\\x80\\x9c&A\\x06I\\x11\\xaf\\xfe"
                                                        "\\xd7P\\xcf\\xa6...')"));
}

// .vtu files beyond what write_vtu() writes (the round trip is in mesh_round_trip_test.cpp).
constexpr const char* kVtuStart =
    "<?xml version=\"1.0\"?>\n"
    "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
    "<UnstructuredGrid>\n"
    "<Piece NumberOfPoints=\"4\" NumberOfCells=\"2\">\n";

TEST(ReadVtu, ReadsCellsSkippingTypesOtherThanTrianglesAndTets) {
  TempDir dir;
  const auto path = dir.write("mixed.vtu", std::string(kVtuStart) +
                                               "<!-- a comment <with> brackets -->\n"
                                               "<Points>\n"
                                               "<DataArray type=\"Float32\" NumberOfComponents=\"3\" "
                                               "format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1"
                                               "</DataArray>\n"
                                               "</Points>\n"
                                               "<Cells>\n"
                                               "<DataArray type=\"Int32\" Name=\"connectivity\" "
                                               "format=\"ascii\">0 1 0 1 2 3</DataArray>\n"
                                               "<DataArray type=\"Int32\" Name=\"offsets\" "
                                               "format=\"ascii\">2 6</DataArray>\n"
                                               "<DataArray type=\"UInt8\" Name=\"types\" "
                                               "format=\"ascii\">3 10</DataArray>\n"
                                               "</Cells>\n</Piece>\n</UnstructuredGrid>\n"
                                               "</VTKFile>\n");
  const MeshData mesh = read_vtu(path);
  EXPECT_EQ(mesh.vertices.cols(), 4);
  EXPECT_EQ(mesh.triangles.cols(), 0);
  ASSERT_EQ(mesh.tetrahedra.cols(), 1);
  EXPECT_EQ(mesh.tetrahedra.col(0), Eigen::Vector4i(0, 1, 2, 3));
}

TEST(ReadVtu, RejectsBinaryDataArrays) {
  TempDir dir;
  const auto path = dir.write("binary.vtu", std::string(kVtuStart) +
                                                "<Points>\n<DataArray type=\"Float64\" "
                                                "NumberOfComponents=\"3\" format=\"binary\">\n"
                                                "AAAAAAAAAAA=\n</DataArray>\n");
  EXPECT_THAT([&] { read_vtu(path); },
              ThrowsInputError("binary.vtu: line 6: DataArray '' has format='binary'; only ascii "
                               "arrays are supported (save the .vtu with ASCII data)"));
}

TEST(ReadVtu, RejectsAppendedData) {
  TempDir dir;
  const auto path = dir.write("appended.vtu", std::string(kVtuStart) + "</Piece>\n" +
                                                  "</UnstructuredGrid>\n<AppendedData "
                                                  "encoding=\"raw\">\n_" +
                                                  random_bytes(31, 256));
  EXPECT_THAT([&] { read_vtu(path); },
              ThrowsInputError("appended.vtu: line 7: appended (binary) data is not supported; "
                               "save the .vtu with ASCII data"));
}

TEST(ReadVtu, RejectsPointsThatDisagreeWithTheCount) {
  TempDir dir;
  const auto path = dir.write("count.vtu", std::string(kVtuStart) +
                                               "<Points>\n<DataArray type=\"Float64\" "
                                               "NumberOfComponents=\"3\" format=\"ascii\">\n"
                                               "0 0 0 1 0 0 0 1 0\n</DataArray>\n</Points>\n");
  EXPECT_THAT(
      [&] { read_vtu(path); },
      ThrowsInputError("count.vtu: line 6: DataArray 'Points' holds 9 values, expected 12 from the "
                       "Piece's NumberOfPoints/NumberOfCells"));
}

TEST(ReadVtu, RejectsOtherXmlAndRandomBytes) {
  TempDir dir;
  const auto polydata = dir.write("poly.vtu", "<VTKFile type=\"PolyData\">\n</VTKFile>\n");
  const auto noise = dir.write("noise.vtu", random_bytes(37, 4096));
  EXPECT_THAT([&] { read_vtu(polydata); },
              ThrowsInputError("poly.vtu: line 1: expected a VTKFile of type UnstructuredGrid, "
                               "found type 'PolyData'"));
  EXPECT_THAT([&] { read_vtu(noise); }, ThrowsInputError("noise.vtu: line 4: not a VTK XML file: "
                                                         "expected <VTKFile>, found "
                                                         "'\\xcfL)\\xf6\\xf9\\x96\\xec\\xd4_\\xa1"
                                                         "\\x93\\xb6\\xbec\\xb0\\x89\\xa4p{\\x04\\x"
                                                         "d1\\x11\\x1b<\\xd0\\xdd<\\x85\\x08\\xcf"
                                                         "\\x0bS+\\xec<\\x13\\xf0\\xaf\\xa1U...'"));
}

}  // namespace
}  // namespace softbench
