// SPDX-License-Identifier: MIT
#include "geometry/input_error.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_validation.h"
#include "harness/cli/commands.h"
#include "harness/report/mesh_info.h"
#include "meshgen/instrument_mesh.h"
#include "meshgen/liver_pipeline.h"
#include "meshgen/surface_simplification.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numbers>
#include <set>
#include <string>

namespace softbench::harness {
namespace {

namespace fs = std::filesystem;

// Checks a generated volume mesh as a user's would be checked, so nothing unusable is written.
MeshInfo checked(const MeshData& volume) {
  static_cast<void>(make_tet_mesh(volume));  // throws InputError naming the problem
  MeshInfo info = inspect_mesh(volume);
  if (!info.usable() || !info.surface.closed_manifold()) {
    throw std::runtime_error(volume.source + ": generated mesh failed validation:\n"
                             + to_text(info));
  }
  return info;
}

void print_summary(const fs::path& file, const MeshInfo& info) {
  std::cout << file.string() << ": " << info.vertices << " vertices, " << info.triangles
            << " boundary triangles, " << info.tetrahedra << " tets, " << info.faces << " faces, "
            << info.edges << " edges, min dihedral " << info.quality->min_dihedral_deg << " deg\n";
}

void write_json(const fs::path& path, const nlohmann::json& json) {
  std::ofstream out(path);
  out << json.dump(2) << "\n";
  if (!out) {
    throw InputError(path.string() + ": cannot write");
  }
}

struct LiverArguments {
  std::string out_dir;
  unsigned seed = meshgen::PhantomOptions{}.seed;
};

void run_liver(const LiverArguments& arguments) {
  const fs::path out_dir = arguments.out_dir;
  fs::create_directories(out_dir);
  meshgen::LiverPipelineOptions options;
  options.phantom.seed = arguments.seed;
  const meshgen::LiverPipelineResult result = meshgen::run_liver_pipeline(options);

  nlohmann::json manifest;
  manifest["generator"] = "softbench mesh liver";
  manifest["seed"] = arguments.seed;
  manifest["phantom_grid"] = {result.stats.grid_size.x(), result.stats.grid_size.y(),
                              result.stats.grid_size.z()};
  manifest["voxel_size_m"] = options.phantom.voxel_size;
  manifest["islands_removed_voxels"] = result.stats.islands_removed;
  manifest["cavities_filled_voxels"] = result.stats.cavities_filled;
  manifest["marching_cubes"] = {{"vertices", result.stats.marching_cubes_vertices},
                                {"triangles", result.stats.marching_cubes_triangles}};
  for (const meshgen::LiverMeshes& meshes : result.meshes) {
    const MeshInfo info = checked(meshes.volume);
    const fs::path volume_file = out_dir / (meshes.name + ".msh");
    write_msh(volume_file, meshes.volume);
    print_summary(volume_file, info);
    const fs::path surface_file = out_dir / (meshes.name + "_surface.obj");
    write_obj(surface_file, MeshData{meshes.surface.vertices, meshes.surface.triangles, {}, ""});
    nlohmann::json entry = to_json(info);
    entry["file"] = volume_file.filename().string();
    entry["surface_vertices"] = meshes.surface.num_vertices();
    entry["surface_triangles"] = meshes.surface.num_triangles();
    manifest["meshes"].push_back(entry);
  }

  const TriMesh instrument = meshgen::make_probe_instrument();
  const fs::path instrument_file = out_dir / "instrument_probe.obj";
  write_obj(instrument_file, MeshData{instrument.vertices, instrument.triangles, {}, ""});
  std::cout << instrument_file.string() << ": " << instrument.num_vertices() << " vertices, "
            << instrument.num_triangles() << " triangles\n";
  manifest["instrument"] = {{"file", instrument_file.filename().string()},
                            {"vertices", instrument.num_vertices()},
                            {"triangles", instrument.num_triangles()}};
  write_json(out_dir / "liver_generation.json", manifest);
}

// The smallest of a tet's six dihedral angles, degrees: pi minus the angle between the outward
// normals of the two faces that meet at each edge.
double min_dihedral_deg(const std::array<Eigen::Vector3d, 4>& corners) {
  std::array<Eigen::Vector3d, 4> normals;  // outward normal of the face opposite corner k
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& a = corners[(k + 1) % 4];
    const Eigen::Vector3d& b = corners[(k + 2) % 4];
    const Eigen::Vector3d& c = corners[(k + 3) % 4];
    Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    if (n.dot(corners[k] - a) > 0.0) {
      n = -n;
    }
    normals[k] = n;
  }
  double smallest = 180.0;
  for (int k = 0; k < 4; ++k) {
    for (int l = k + 1; l < 4; ++l) {
      const double cosine = std::clamp(normals[k].dot(normals[l]), -1.0, 1.0);
      smallest = std::min(smallest, 180.0 - std::acos(cosine) * 180.0 / std::numbers::pi);
    }
  }
  return smallest;
}

// TetGen's dihedral bound is a refinement target, not a guarantee: says so when the mesh falls
// short of it, with how far and where.
void check_min_dihedral(const MeshData& volume,
                        const MeshInfo& info,
                        const meshgen::TetrahedralizeOptions& options) {
  const double bound = options.min_dihedral_deg;
  if (!(bound > 0.0) || !info.quality || info.quality->min_dihedral_deg >= bound) {
    return;
  }
  std::set<std::array<int, 3>> surface;
  for (Eigen::Index t = 0; t < volume.triangles.cols(); ++t) {
    std::array<int, 3> face{volume.triangles(0, t), volume.triangles(1, t), volume.triangles(2, t)};
    std::sort(face.begin(), face.end());
    surface.insert(face);
  }
  int below = 0;
  int on_surface = 0;
  for (Eigen::Index t = 0; t < volume.tetrahedra.cols(); ++t) {
    std::array<Eigen::Vector3d, 4> corners;
    for (int k = 0; k < 4; ++k) {
      corners[k] = volume.vertices.col(volume.tetrahedra(k, t));
    }
    if (min_dihedral_deg(corners) >= bound) {
      continue;
    }
    ++below;
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> face{volume.tetrahedra((k + 1) % 4, t), volume.tetrahedra((k + 2) % 4, t),
                              volume.tetrahedra((k + 3) % 4, t)};
      std::sort(face.begin(), face.end());
      if (surface.count(face) > 0) {
        ++on_surface;
        break;
      }
    }
  }
  std::cerr << "warning: --min-dihedral " << bound << ": the smallest dihedral angle is "
            << info.quality->min_dihedral_deg << " deg (" << below << " of "
            << volume.tetrahedra.cols() << " tets below " << bound << " deg, " << on_surface
            << " of them with a face on the surface). TetGen's dihedral bound (-q"
            << options.radius_edge_ratio << "/" << bound
            << ") is a target, not a guarantee: TetGen splits the tets below it but may leave "
               "some (it rejects split points that would encroach on the surface, which it keeps "
               "as given (-Y), and a tight radius-edge ratio competes with the bound). The mesh "
               "was written; for a better one try a larger --radius-edge-ratio, a smaller bound, "
               "or --surface-vertices to remesh the surface first.\n";
}

struct TetrahedralizeArguments {
  std::string surface;
  std::string out_dir;
  int surface_vertices = 0;
  meshgen::TetrahedralizeOptions options;
};

void run_tetrahedralize(const TetrahedralizeArguments& arguments) {
  TriMesh surface = make_closed_surface(read_mesh(arguments.surface));
  if (arguments.surface_vertices > 0) {
    surface = meshgen::simplify_surface(surface, arguments.surface_vertices);
  }
  MeshData volume = meshgen::tetrahedralize(surface, arguments.options);
  const fs::path out_dir = arguments.out_dir;
  fs::create_directories(out_dir);
  const fs::path volume_file = out_dir / (fs::path(arguments.surface).stem().string() + ".msh");
  volume.source = volume_file.string();
  const MeshInfo info = checked(volume);
  write_msh(volume_file, volume);
  print_summary(volume_file, info);
  check_min_dihedral(volume, info, arguments.options);
}

}  // namespace

void add_mesh_generation_commands(CLI::App& mesh) {
  auto liver_arguments = std::make_shared<LiverArguments>();
  CLI::App* liver = mesh.add_subcommand(
      "liver", "Regenerate the shipped liver meshes from the synthetic CT phantom (thesis ch. 2)");
  liver->add_option("--out", liver_arguments->out_dir, "output folder")->required();
  liver->add_option("--seed", liver_arguments->seed, "noise seed of the CT phantom")
      ->capture_default_str();
  liver->callback([liver_arguments] { run_liver(*liver_arguments); });

  auto tet_arguments = std::make_shared<TetrahedralizeArguments>();
  CLI::App* tetrahedralize = mesh.add_subcommand(
      "tetrahedralize", "Fill a closed surface with quality tetrahedra (TetGen)");
  tetrahedralize->add_option("surface", tet_arguments->surface, "closed surface mesh file")
      ->required();
  tetrahedralize->add_option("--out", tet_arguments->out_dir, "output folder")->required();
  tetrahedralize
      ->add_option("--surface-vertices", tet_arguments->surface_vertices,
                   "remesh the surface to about this many well-shaped vertices first (0: keep it)")
      ->check(CLI::NonNegativeNumber);
  tetrahedralize
      ->add_option("--max-volume", tet_arguments->options.max_volume,
                   "largest tet volume, in the surface's units cubed (0: no bound)")
      ->capture_default_str();
  tetrahedralize
      ->add_option("--radius-edge-ratio", tet_arguments->options.radius_edge_ratio,
                   "quality bound on circumradius / shortest edge (>= 1.1)")
      ->capture_default_str();
  tetrahedralize
      ->add_option("--min-dihedral", tet_arguments->options.min_dihedral_deg,
                   "quality target on dihedral angles, degrees (TetGen -q<ratio>/<angle>; 0: "
                   "none). A target, not a guarantee: TetGen splits tets below it where it can, "
                   "but keeps the surface as given and weighs it against the radius-edge ratio; "
                   "the command measures the result and warns when its smallest angle falls "
                   "short")
      ->capture_default_str();
  tetrahedralize->callback([tet_arguments] { run_tetrahedralize(*tet_arguments); });
}

}  // namespace softbench::harness
