// SPDX-License-Identifier: MIT
// Writes the fuzz targets' seed corpora, fuzz/corpus/<target>/, and the model-parameter
// dictionary, fuzz/dict/model_params.dict: small meshes made in code (a box of six tets, its
// surface, an icosphere) in every format, through the project's writers where it has one and
// spelt out here where it has none (MSH 1 and 4.1, STL, legacy VTK), and a corner of the
// shipped liver and probe (their first 40 vertices); the shipped scenes and three
// that use every scene key; each registered model's defaults, its documented settings and the
// shipped scenes' blocks. The seeds are committed; rerun after a format or schema change:
//   build/fuzz/fuzz/fuzz_make_seeds fuzz
#include "geometry/mesh_io.h"
#include "geometry/mesh_topology.h"
#include "geometry/shape_meshes.h"
#include "models/json_file.h"
#include "models/model_registry.h"
#include "scenes/shipped_data.h"

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

namespace {

namespace fs = std::filesystem;
using softbench::MeshData;

fs::path corpus_root;

void write_seed(const std::string& target, const std::string& name, const std::string& bytes) {
  const fs::path folder = corpus_root / "corpus" / target;
  fs::create_directories(folder);
  std::ofstream out(folder / name, std::ios::binary | std::ios::trunc);
  out << bytes;
}

std::string read_whole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A file a project writer made, as bytes: written to a scratch folder and read back.
template <typename Write>
std::string written_by(const std::string& name, Write write) {
  const fs::path folder = fs::temp_directory_path() / "softbench-make-seeds";
  fs::create_directories(folder);
  write(folder / name);
  std::string bytes = read_whole(folder / name);
  fs::remove_all(folder);
  return bytes;
}

// A 10 x 7 x 5 cm box in 6 tets with its 12 boundary triangles: every reader's mesh.
MeshData box_with_surface() {
  MeshData mesh = softbench::box_tets(1, 1, 1, 0.1, 0.07, 0.05);
  mesh.triangles = softbench::boundary_triangles(mesh.tetrahedra);
  return mesh;
}

// The part of a shipped mesh on its first `count` vertices: the elements among them.
MeshData shipped_part(const std::string& name, Eigen::Index count) {
  const MeshData whole = softbench::read_mesh(softbench::scenes::shipped_data_file(name));
  MeshData part;
  part.vertices = whole.vertices.leftCols(count);
  const auto keep = [count](const auto& cells) {
    Eigen::Matrix<int, std::decay_t<decltype(cells)>::RowsAtCompileTime, Eigen::Dynamic> kept(
        cells.rows(), 0);
    for (Eigen::Index c = 0; c < cells.cols(); ++c) {
      if (cells.col(c).maxCoeff() < count) {
        kept.conservativeResize(Eigen::NoChange, kept.cols() + 1);
        kept.col(kept.cols() - 1) = cells.col(c);
      }
    }
    return kept;
  };
  part.triangles = keep(whole.triangles);
  part.tetrahedra = keep(whole.tetrahedra);
  return part;
}

MeshData surface_of(const MeshData& mesh) {
  MeshData surface;
  surface.vertices = mesh.vertices;
  surface.triangles = mesh.triangles;
  return surface;
}

std::string coordinates(const MeshData& mesh, Eigen::Index v) {
  std::ostringstream out;
  out.precision(17);
  out << mesh.vertices(0, v) << ' ' << mesh.vertices(1, v) << ' ' << mesh.vertices(2, v);
  return out.str();
}

template <int Rows>
std::string indices(const Eigen::Matrix<int, Rows, Eigen::Dynamic>& cells, Eigen::Index c,
                    int offset) {
  std::string text;
  for (Eigen::Index k = 0; k < Rows; ++k) {
    text += (k == 0 ? "" : " ") + std::to_string(cells(k, c) + offset);
  }
  return text;
}

// ---- OBJ
void obj_seeds() {
  const MeshData box = box_with_surface();
  write_seed("fuzz_obj", "box_surface.obj",
             written_by("s.obj", [&](const fs::path& p) { softbench::write_obj(p, surface_of(box)); }));
  const softbench::TriMesh sphere = softbench::icosphere(1, 0.05);
  MeshData sphere_data;
  sphere_data.vertices = sphere.vertices;
  sphere_data.triangles = sphere.triangles;
  const MeshData probe = shipped_part("instrument_probe.obj", 40);
  write_seed("fuzz_obj", "instrument_probe_part.obj",
             written_by("p.obj", [&](const fs::path& p) { softbench::write_obj(p, probe); }));
  write_seed("fuzz_obj", "icosphere.obj",
             written_by("s.obj", [&](const fs::path& p) { softbench::write_obj(p, sphere_data); }));
  // The forms an exporter writes: groups, materials, texture and normal indices, negative
  // indices, polygons, comments, CRLF.
  write_seed("fuzz_obj", "forms.obj",
             "# exported\r\nmtllib a.mtl\r\no tet\r\ng default\r\n"
             "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nv 0 0 1\r\nv 1 1 0\r\n"
             "vt 0.5 0.5\r\nvn 0 0 1\r\nvp 0.2\r\nusemtl red\r\ns off\r\n"
             "f 1/1/1 3/1/1 2/1/1\r\nf 1//1 2//1 4//1 # note\r\nf -5/1 -2/1 -3/1\r\n"
             "f 2 5 3 4\r\nl 1 2\r\np 3\r\n");
}

// ---- MSH
std::string msh1(const MeshData& mesh) {
  std::string text = "$NOD\n" + std::to_string(mesh.vertices.cols()) + "\n";
  for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v) {
    text += std::to_string(v + 1) + " " + coordinates(mesh, v) + "\n";
  }
  const Eigen::Index count = 1 + mesh.triangles.cols() + mesh.tetrahedra.cols();
  text += "$ENDNOD\n$ELM\n" + std::to_string(count) + "\n";
  int id = 1;
  text += std::to_string(id++) + " 15 1 1 1 1\n";  // a point, skipped
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    text += std::to_string(id++) + " 2 2 2 3 " + indices(mesh.triangles, t, 1) + "\n";
  }
  for (Eigen::Index t = 0; t < mesh.tetrahedra.cols(); ++t) {
    text += std::to_string(id++) + " 4 3 3 4 " + indices(mesh.tetrahedra, t, 1) + "\n";
  }
  return text + "$ENDELM\n";
}

std::string msh41(const MeshData& mesh) {
  const Eigen::Index nodes = mesh.vertices.cols();
  std::string text =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$PhysicalNames\n1\n3 1 \"body\"\n$EndPhysicalNames\n"
      "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 1 1 0\n$EndEntities\n";
  // Two node blocks (the first vertex alone, then the rest) with tags 10, 20, 30, ...
  text += "$Nodes\n2 " + std::to_string(nodes) + " 10 " + std::to_string(10 * nodes) + "\n";
  text += "0 1 0 1\n10\n" + coordinates(mesh, 0) + "\n";
  text += "3 1 0 " + std::to_string(nodes - 1) + "\n";
  for (Eigen::Index v = 1; v < nodes; ++v) {
    text += std::to_string(10 * (v + 1)) + "\n";
  }
  for (Eigen::Index v = 1; v < nodes; ++v) {
    text += coordinates(mesh, v) + "\n";
  }
  text += "$EndNodes\n";
  const auto tags = [](const auto& cells, Eigen::Index c) {
    std::string line;
    for (Eigen::Index k = 0; k < cells.rows(); ++k) {
      line += " " + std::to_string(10 * (cells(k, c) + 1));
    }
    return line;
  };
  const Eigen::Index elements = 1 + mesh.triangles.cols() + mesh.tetrahedra.cols();
  text += "$Elements\n3 " + std::to_string(elements) + " 1 " + std::to_string(elements) + "\n";
  int id = 1;
  text += "1 1 1 1\n" + std::to_string(id++) + " 10 20\n";  // a line, skipped
  text += "2 1 2 " + std::to_string(mesh.triangles.cols()) + "\n";
  for (Eigen::Index t = 0; t < mesh.triangles.cols(); ++t) {
    text += std::to_string(id++) + tags(mesh.triangles, t) + "\n";
  }
  text += "3 1 4 " + std::to_string(mesh.tetrahedra.cols()) + "\n";
  for (Eigen::Index t = 0; t < mesh.tetrahedra.cols(); ++t) {
    text += std::to_string(id++) + tags(mesh.tetrahedra, t) + "\n";
  }
  return text + "$EndElements\n";
}

void msh_seeds() {
  const MeshData box = box_with_surface();
  write_seed("fuzz_msh", "box_v22.msh",
             written_by("b.msh", [&](const fs::path& p) { softbench::write_msh(p, box); }));
  const MeshData liver = shipped_part("liver.msh", 40);
  write_seed("fuzz_msh", "liver_part_v22.msh",
             written_by("l.msh", [&](const fs::path& p) { softbench::write_msh(p, liver); }));
  write_seed("fuzz_msh", "box_v1.msh", msh1(box));
  write_seed("fuzz_msh", "box_v41.msh", msh41(box));
}

// ---- TetGen: the three files in one input, split at "#@ele" and "#@face" (fuzz_tetgen.cpp).
void tetgen_seeds() {
  const MeshData box = box_with_surface();
  const fs::path folder = fs::temp_directory_path() / "softbench-make-seeds";
  fs::create_directories(folder);
  softbench::write_tetgen(folder / "box", box);
  write_seed("fuzz_tetgen", "box_0based.tetgen",
             read_whole(folder / "box.node") + "#@ele\n" + read_whole(folder / "box.ele")
                 + "#@face\n" + read_whole(folder / "box.face"));
  fs::remove_all(folder);
  // 1-based, with an attribute and boundary markers, comments, as TetGen itself writes.
  std::string node = "# box.node\n" + std::to_string(box.vertices.cols()) + " 3 1 1\n";
  for (Eigen::Index v = 0; v < box.vertices.cols(); ++v) {
    node += std::to_string(v + 1) + "  " + coordinates(box, v) + "  0.5  1\n";
  }
  std::string ele = std::to_string(box.tetrahedra.cols()) + " 4 1\n";
  for (Eigen::Index t = 0; t < box.tetrahedra.cols(); ++t) {
    ele += std::to_string(t + 1) + "  " + indices(box.tetrahedra, t, 1) + "  1\n";
  }
  ele += "# Generated by tetgen -pq1.414a0.1\n";
  std::string face = std::to_string(box.triangles.cols()) + " 1\n";
  for (Eigen::Index t = 0; t < box.triangles.cols(); ++t) {
    face += std::to_string(t + 1) + "  " + indices(box.triangles, t, 1) + "  -1\n";
  }
  write_seed("fuzz_tetgen", "box_1based_markers.tetgen",
             node + "#@ele\n" + ele + "#@face\n" + face);
  write_seed("fuzz_tetgen", "box_nodes_only.tetgen", node);
}

// ---- STL
template <typename T>
void put_little(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
  }
  bytes.append(raw, sizeof(T));
}

void stl_seeds() {
  const MeshData box = box_with_surface();
  std::string ascii = "solid box\n";
  std::string binary = "solid box exported as binary";
  binary.resize(80, ' ');
  put_little(binary, static_cast<std::uint32_t>(box.triangles.cols()));
  for (Eigen::Index t = 0; t < box.triangles.cols(); ++t) {
    ascii += "  facet normal 0 0 0\n    outer loop\n";
    for (int k = 0; k < 3; ++k) {
      ascii += "      vertex " + coordinates(box, box.triangles(k, t)) + "\n";
    }
    ascii += "    endloop\n  endfacet\n";
    for (int k = 0; k < 3; ++k) {
      put_little(binary, 0.0f);  // the normal
    }
    for (int k = 0; k < 3; ++k) {
      for (int axis = 0; axis < 3; ++axis) {
        put_little(binary, static_cast<float>(box.vertices(axis, box.triangles(k, t))));
      }
    }
    put_little(binary, std::uint16_t{0});
  }
  ascii += "endsolid box\n";
  write_seed("fuzz_stl", "box_ascii.stl", ascii);
  write_seed("fuzz_stl", "box_binary.stl", binary);
}

// ---- legacy VTK
template <typename T>
void put_big(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::little) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      std::swap(raw[i], raw[sizeof(T) - 1 - i]);
    }
  }
  bytes.append(raw, sizeof(T));
}

void vtk_seeds() {
  const MeshData box = box_with_surface();
  const Eigen::Index points = box.vertices.cols();
  const Eigen::Index tris = box.triangles.cols();
  const Eigen::Index tets = box.tetrahedra.cols();
  const std::string n = std::to_string(points);
  // ASCII unstructured grid: field data, triangles, tets and a skipped vertex cell, cell data.
  std::string grid = "# vtk DataFile Version 3.0\nbox\nASCII\nDATASET UNSTRUCTURED_GRID\n"
                     "FIELD FieldData 1\nTIME 1 1 double\n0.5\nPOINTS " + n + " double\n";
  for (Eigen::Index v = 0; v < points; ++v) {
    grid += coordinates(box, v) + "\n";
  }
  const Eigen::Index cells = tris + tets + 1;
  grid += "CELLS " + std::to_string(cells) + " " + std::to_string(4 * tris + 5 * tets + 2) + "\n";
  for (Eigen::Index t = 0; t < tris; ++t) {
    grid += "3 " + indices(box.triangles, t, 0) + "\n";
  }
  for (Eigen::Index t = 0; t < tets; ++t) {
    grid += "4 " + indices(box.tetrahedra, t, 0) + "\n";
  }
  grid += "1 0\nCELL_TYPES " + std::to_string(cells) + "\n";
  for (Eigen::Index t = 0; t < tris; ++t) {
    grid += "5\n";
  }
  for (Eigen::Index t = 0; t < tets; ++t) {
    grid += "10\n";
  }
  grid += "1\nCELL_DATA " + std::to_string(cells) + "\nSCALARS id int 1\nLOOKUP_TABLE default\n";
  write_seed("fuzz_vtk", "box_grid_ascii.vtk", grid);

  // Version 5.1: OFFSETS and CONNECTIVITY, with METADATA.
  std::string v51 = "# vtk DataFile Version 5.1\nbox\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS "
                    + n + " float\n";
  for (Eigen::Index v = 0; v < points; ++v) {
    v51 += coordinates(box, v) + "\n";
  }
  v51 += "METADATA\nINFORMATION 0\n\nCELLS " + std::to_string(tets + 1) + " "
         + std::to_string(4 * tets) + "\nOFFSETS vtktypeint64\n";
  for (Eigen::Index t = 0; t <= tets; ++t) {
    v51 += std::to_string(4 * t) + "\n";
  }
  v51 += "CONNECTIVITY vtktypeint64\n";
  for (Eigen::Index t = 0; t < tets; ++t) {
    v51 += indices(box.tetrahedra, t, 0) + "\n";
  }
  v51 += "CELL_TYPES " + std::to_string(tets) + "\n";
  for (Eigen::Index t = 0; t < tets; ++t) {
    v51 += "10\n";
  }
  write_seed("fuzz_vtk", "box_grid_v51.vtk", v51);

  // ASCII polydata: the surface as polygons and a triangle strip.
  std::string poly = "# vtk DataFile Version 2.0\nsurface\nASCII\nDATASET POLYDATA\nPOINTS " + n
                     + " float\n";
  for (Eigen::Index v = 0; v < points; ++v) {
    poly += coordinates(box, v) + "\n";
  }
  poly += "VERTICES 1 2\n1 0\nLINES 1 3\n2 0 1\nPOLYGONS " + std::to_string(tris) + " "
          + std::to_string(4 * tris) + "\n";
  for (Eigen::Index t = 0; t < tris; ++t) {
    poly += "3 " + indices(box.triangles, t, 0) + "\n";
  }
  poly += "TRIANGLE_STRIPS 1 5\n4 0 1 2 3\nPOINT_DATA " + n + "\n";
  write_seed("fuzz_vtk", "box_polydata_ascii.vtk", poly);

  // BINARY (big-endian) grid and polydata.
  std::string bgrid = "# vtk DataFile Version 3.0\nbox\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS "
                      + n + " float\n";
  for (Eigen::Index v = 0; v < points; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      put_big(bgrid, static_cast<float>(box.vertices(axis, v)));
    }
  }
  bgrid += "\nCELLS " + std::to_string(tets) + " " + std::to_string(5 * tets) + "\n";
  for (Eigen::Index t = 0; t < tets; ++t) {
    put_big(bgrid, std::int32_t{4});
    for (int k = 0; k < 4; ++k) {
      put_big(bgrid, static_cast<std::int32_t>(box.tetrahedra(k, t)));
    }
  }
  bgrid += "\nCELL_TYPES " + std::to_string(tets) + "\n";
  for (Eigen::Index t = 0; t < tets; ++t) {
    put_big(bgrid, std::int32_t{10});
  }
  bgrid += "\n";
  write_seed("fuzz_vtk", "box_grid_binary.vtk", bgrid);

  std::string bpoly = "# vtk DataFile Version 4.2\nsurface\nBINARY\nDATASET POLYDATA\nPOINTS " + n
                      + " double\n";
  for (Eigen::Index v = 0; v < points; ++v) {
    for (int axis = 0; axis < 3; ++axis) {
      put_big(bpoly, box.vertices(axis, v));
    }
  }
  bpoly += "\nPOLYGONS " + std::to_string(tris) + " " + std::to_string(4 * tris) + "\n";
  for (Eigen::Index t = 0; t < tris; ++t) {
    put_big(bpoly, std::int32_t{3});
    for (int k = 0; k < 3; ++k) {
      put_big(bpoly, static_cast<std::int32_t>(box.triangles(k, t)));
    }
  }
  bpoly += "\n";
  write_seed("fuzz_vtk", "box_polydata_binary.vtk", bpoly);
}

// ---- VTU
void vtu_seeds() {
  const MeshData box = box_with_surface();
  const Eigen::Matrix3Xd displacement = 0.01 * box.vertices;
  const softbench::VertexField field{"displacement", &displacement};
  write_seed("fuzz_vtu", "box_with_field.vtu", written_by("b.vtu", [&](const fs::path& p) {
               softbench::write_vtu(p, box, std::span(&field, 1));
             }));
  MeshData tets_only = box;
  tets_only.triangles.resize(3, 0);
  write_seed("fuzz_vtu", "box_tets.vtu",
             written_by("b.vtu", [&](const fs::path& p) { softbench::write_vtu(p, tets_only); }));
}

// ---- scenes
void scene_seeds() {
  const fs::path scenes = softbench::scenes::shipped_data_dir().parent_path();
  for (const auto& entry : fs::directory_iterator(scenes)) {
    if (entry.path().extension() == ".json") {
      write_seed("fuzz_scene", entry.path().filename().string(), read_whole(entry.path()));
    }
  }
  // Every key the schema has (scenes/README.md), in two scenes: a scene grasp and an instrument
  // grasp cannot go together.
  write_seed("fuzz_scene", "every_key_grasp.json", R"({
  "name": "every key", "description": "a grasp, supports, an initial velocity",
  "mesh": "data/liver.msh",
  "material": {"young_modulus": 5000, "poisson_ratio": 0.45, "density": 1060},
  "gravity": {"acceleration": [0, 0, -9.81], "off_at": 1.5},
  "time": {"dt": 0.01, "duration": 2},
  "fixed": {"vertices": [0, 1, 2], "box": {"min": [-0.1, -0.1, -0.1], "max": [0.1, -0.05, 0.1]},
            "plane": {"point": [0, -0.045, 0.045], "normal": [0, -1, 1], "tolerance": 0.016}},
  "supports": [{"point": [0, 0, -0.1], "normal": [0, 0, 1], "tolerance": 1e-3},
               {"point": [0, 0, 0], "normal": [1, 0, 0]}],
  "initial_velocity": {"linear": [0.1, 0, 0], "angular": [0, 0, 1], "center": [0, 0, 0]},
  "grasp": {"center": [0.1, 0, 0], "radius": 0.02, "start": 0.5, "release": 1.5,
            "path": [{"t": 0.5, "offset": [0, 0, 0]}, {"t": 1.0, "offset": [0, 0.01, -0.01]}]},
  "limits": {"max_speed": 20, "max_displacement": 5},
  "requirements": {"steps_per_second": 60, "accuracy": 0.05,
                   "outputs": ["surface", "volume", "contact_force"]},
  "models": {"mass_spring": {"integrator": "symplectic_euler"}, "shape_matching": {}}
}
)");
  write_seed("fuzz_scene", "every_key_instrument.json", R"({
  "name": "instrument", "mesh": "data/liver.msh",
  "material": {"young_modulus": 3000, "poisson_ratio": 0.3, "density": 1060},
  "gravity": [0, 0, -9.81],
  "time": {"duration": 1},
  "instrument": {
    "mesh": "data/instrument_probe.obj", "start": 0.2, "release": 0.8, "contact_margin": 1e-4,
    "path": [{"t": 0, "position": [0, 0, 0.2]},
             {"t": 0.5, "position": [0, 0, 0.1], "rotation": {"axis": [1, 0, 0], "degrees": -135}},
             {"t": 1, "position": [0, 0, 0.2], "rotation": {"axis": [0, 1, 1], "degrees": 30}}]
  }
}
)");
  write_seed("fuzz_scene", "instrument_grasp.json", R"({
  "name": "g", "mesh": "data/liver.msh",
  "material": {"young_modulus": 3000, "poisson_ratio": 0.3, "density": 1060},
  "time": {"duration": 1, "dt": 0.5},
  "instrument": {"mesh": "data/instrument_probe.obj",
                 "grasp": {"center": [0.1, 0, 0], "radius": 0.05, "start": 0.1, "release": 0.9},
                 "path": [{"t": 0, "position": [0, 0, 0]}]}
}
)");
}

// ---- model parameter blocks, and the dictionary of their names
void model_seeds() {
  const softbench::ModelRegistry& models = softbench::builtin_models();
  std::set<std::string> words;
  nlohmann::json all_defaults = nlohmann::json::object();
  for (const std::string& name : models.names()) {
    const softbench::ModelInfo& info = models.at(name);
    words.insert(name);
    nlohmann::json defaults = nlohmann::json::object();
    for (const softbench::ParameterDoc& parameter : info.parameters) {
      defaults[parameter.name] = parameter.default_value;
      words.insert(parameter.name);
      // The spellings a description quotes ("cg", "young_modulus") are the choices' values.
      const std::string& text = parameter.description;
      for (std::size_t open = text.find('"'); open != std::string::npos;) {
        const std::size_t close = text.find('"', open + 1);
        if (close == std::string::npos) {
          break;
        }
        const std::string word = text.substr(open + 1, close - open - 1);
        if (!word.empty() && word.find(' ') == std::string::npos) {
          words.insert(word);
        }
        open = text.find('"', close + 1);
      }
    }
    all_defaults[name] = defaults;
    write_seed("fuzz_model_params", name + "_defaults.json",
               nlohmann::json{{name, defaults}}.dump(2) + "\n");
    int variant = 0;
    const auto write_variant = [&](const nlohmann::json& settings) {
      if (settings.empty()) {
        return;
      }
      write_seed("fuzz_model_params", name + "_" + std::to_string(++variant) + ".json",
                 nlohmann::json{{name, settings}}.dump() + "\n");
    };
    for (const nlohmann::json& settings : info.speed_settings) {
      write_variant(settings);
    }
    write_variant(info.settling_damping);
    write_variant(info.stiffness_axis.fixed_params);
    write_variant(info.calibration.fixed);
  }
  write_seed("fuzz_model_params", "all_defaults.json", all_defaults.dump() + "\n");
  // Every shipped scene's "models" object, as a scene holds it (comments and all stripped).
  const fs::path scenes = softbench::scenes::shipped_data_dir().parent_path();
  for (const auto& entry : fs::directory_iterator(scenes)) {
    if (entry.path().extension() != ".json") {
      continue;
    }
    const nlohmann::json scene = softbench::read_json_file(entry.path());
    if (scene.contains("models")) {
      write_seed("fuzz_model_params", "scene_" + entry.path().stem().string() + ".json",
                 scene["models"].dump(2) + "\n");
    }
  }

  const fs::path dict = corpus_root / "dict" / "model_params.dict";
  fs::create_directories(dict.parent_path());
  std::ofstream out(dict, std::ios::trunc);
  out << "# Written by fuzz/make_seeds.cpp from the model registry: the models, their parameters\n"
         "# and the spellings their descriptions quote. Then JSON's own tokens.\n";
  for (const std::string& word : words) {
    out << "\"\\\"" << word << "\\\"\"\n";
  }
  for (const char* token : {"{", "}", "[", "]", ":", ",", "null", "true", "false", "-1", "0",
                            "1e308", "-1e-308", "1.5", "2147483648", "-9223372036854775809",
                            "18446744073709551616", "\\\"\\\\u0000\\\"", "//", "/*", "*/"}) {
    out << "\"" << token << "\"\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_make_seeds FUZZ_FOLDER (the repository's fuzz/)\n";
    return 2;
  }
  corpus_root = argv[1];
  obj_seeds();
  msh_seeds();
  tetgen_seeds();
  stl_seeds();
  vtk_seeds();
  vtu_seeds();
  scene_seeds();
  model_seeds();
  std::cout << "seeds written under " << (corpus_root / "corpus").string() << "\n";
  return 0;
}
