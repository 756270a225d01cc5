// SPDX-License-Identifier: MIT
// The implicit models' linear solvers on a block system built here: an elasticity-like matrix
// A = m I + sum over edges of G_e^T B_e G_e (B_e a random symmetric positive semi-definite 3x3
// block, G_e x = x_i - x_j) on a box of tets. Symmetric positive definite, with the sparsity and
// the conditioning of a backward Euler system (the mass term m against the stiffness).
#include "models/system_solver.h"

#include "geometry/mesh_topology.h"
#include "geometry/mesh_validation.h"
#include "geometry/vertex_order.h"
#include "models/block_pattern.h"
#include "models/coarse_space.h"
#include "models/ssor_solver.h"
#include "models/warm_start.h"
#include "tests/test_meshes.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <span>
#include <string>
#include <vector>

namespace softbench {
namespace {

using Kind = LinearSolverOptions::Kind;
using Preconditioner = LinearSolverOptions::Preconditioner;

/// The stiffness dominates the mass term a thousandfold, as dt^2 K does M on the liver.
constexpr double kMass = 1e-3;

struct BlockSystem {
  BlockPattern pattern;
  Eigen::MatrixXd dense;  ///< the same matrix, for exact answers
};

/// `with_dense`: also the dense matrix, for exact answers (small systems only).
BlockSystem elastic_like_system(unsigned seed,
                                const MeshData& box = test::box_tets(6, 4, 3),
                                bool with_dense = true) {
  const Eigen::Matrix2Xi edges = unique_edges(box.tetrahedra);
  const auto num_vertices = static_cast<int>(box.vertices.cols());
  BlockSystem system{BlockPattern(num_vertices, edges), Eigen::MatrixXd()};
  if (with_dense) {
    system.dense.setZero(3 * num_vertices, 3 * num_vertices);
  }
  std::vector<Eigen::Matrix3d> diagonal(static_cast<std::size_t>(num_vertices),
                                        kMass * Eigen::Matrix3d::Identity());
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (Eigen::Index e = 0; e < edges.cols(); ++e) {
    Eigen::Matrix3d g;
    for (int k = 0; k < 9; ++k) {
      g(k) = entry(random);
    }
    const Eigen::Matrix3d block = g * g.transpose();
    const int i = edges(0, e);
    const int j = edges(1, e);
    diagonal[static_cast<std::size_t>(i)] += block;
    diagonal[static_cast<std::size_t>(j)] += block;
    if (with_dense) {
      system.dense.block<3, 3>(3 * i, 3 * j) -= block;
      system.dense.block<3, 3>(3 * j, 3 * i) -= block;
    }
    system.pattern.set(system.pattern.edge_block(static_cast<int>(e)), -block);
    system.pattern.set(system.pattern.edge_block_transposed(static_cast<int>(e)), -block);
  }
  for (int v = 0; v < num_vertices; ++v) {
    system.pattern.set(system.pattern.vertex_block(v), diagonal[static_cast<std::size_t>(v)]);
    if (with_dense) {
      system.dense.block<3, 3>(3 * v, 3 * v) = diagonal[static_cast<std::size_t>(v)];
    }
  }
  return system;
}

Eigen::VectorXd random_vector(Eigen::Index size, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) {
    v(i) = normal(random);
  }
  return v;
}

double energy_norm(const Eigen::MatrixXd& a, const Eigen::VectorXd& v) {
  return std::sqrt(v.dot(a * v));
}

LinearSolverOptions cg_options(Preconditioner preconditioner, double tolerance) {
  LinearSolverOptions options;
  options.kind = Kind::kConjugateGradient;
  options.preconditioner = preconditioner;
  options.tolerance = tolerance;
  options.max_iterations = 10000;
  return options;
}

/// Solves `system` for `b` from zero with `options` and checks what such a solve delivers: it
/// converged, its energy-norm error is within the tolerance (the estimate is a lower bound that
/// tightens with its delay; a factor 10 covers its slack), and the residual it reports is the
/// system's, |b - A x| / |b| (Jacobi's updated recursively: round-off apart), not a transformed
/// one. Returns x; `report` (if given) gets the report.
Eigen::VectorXd solve_within_tolerance(const BlockSystem& system,
                                       const Eigen::VectorXd& b,
                                       const LinearSolverOptions& options,
                                       SolveReport* report = nullptr) {
  const Eigen::VectorXd exact = system.dense.ldlt().solve(b);
  const auto solver = make_system_solver(options, system.pattern);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  const SolveReport solved = solver->solve(system.pattern, b, x, nullptr);
  EXPECT_TRUE(solved.converged);
  EXPECT_LT(energy_norm(system.dense, x - exact),
            10.0 * options.tolerance * energy_norm(system.dense, exact));
  EXPECT_NEAR(solved.residual, (b - system.dense * x).norm() / b.norm(),
              1e-6 * solved.residual + 1e-12);
  if (report != nullptr) {
    *report = solved;
  }
  return x;
}

TEST(SystemSolver, EachPreconditionerMeetsTheEnergyNormTolerance) {
  const BlockSystem system = elastic_like_system(1);
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 2);
  for (const Preconditioner preconditioner : {Preconditioner::kJacobi, Preconditioner::kSsor}) {
    solve_within_tolerance(system, b, cg_options(preconditioner, 1e-6));
  }
}

TEST(SystemSolver, SymmetricGaussSeidelNeedsFewerIterationsThanJacobi) {
  const BlockSystem system = elastic_like_system(3);
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 4);
  int iterations[2] = {0, 0};
  int k = 0;
  for (const Preconditioner preconditioner : {Preconditioner::kJacobi, Preconditioner::kSsor}) {
    const auto solver = make_system_solver(cg_options(preconditioner, 1e-8), system.pattern);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    iterations[k++] = solver->solve(system.pattern, b, x, nullptr).iterations;
  }
  // Symmetric Gauss-Seidel squares about half of Jacobi's condition number away.
  EXPECT_LT(iterations[1], 0.7 * iterations[0]) << iterations[0] << " vs " << iterations[1];
}

/// The box the parts tests solve on, numbered for locality and cut into two parts and a
/// separator (the sweeps then run on the parts side by side).
struct PartedBox {
  MeshData data;
  PartitionedOrder cut;
};

PartedBox parted_box() {
  const TetMesh box = make_tet_mesh(test::box_tets(16, 4, 3));
  const TetMesh local = renumbered(box, reverse_cuthill_mckee(box.tets(), box.num_vertices()));
  PartedBox result;
  result.cut = partitioned(local.tets(), local.num_vertices(), 2);
  EXPECT_EQ(result.cut.offsets.size(), 4U);
  const TetMesh mesh = renumbered(local, result.cut.order);
  result.data.vertices = mesh.rest_positions();
  result.data.tetrahedra = mesh.tets();
  return result;
}

/// elastic_like_system (no dense matrix) on parted_box(), its parts set.
BlockSystem parted_box_system(unsigned seed, PartitionedOrder* cut_out = nullptr) {
  const PartedBox box = parted_box();
  BlockSystem system = elastic_like_system(seed, box.data, /*with_dense=*/false);
  system.pattern.set_parts(box.cut.offsets);
  if (cut_out != nullptr) {
    *cut_out = box.cut;
  }
  return system;
}

TEST(SystemSolver, SsorSweepsPartsSideBySideToTheSameAnswerOnAnyThreadCount) {
  // A box numbered for locality and cut into two parts and a separator: the sweeps run on the
  // parts side by side. The preconditioner is still a symmetric Gauss-Seidel of the same
  // matrix (in another vertex order), so it meets the tolerance as the one-part order does, in
  // about as many iterations, and its answer does not depend on the thread count.
  const PartedBox box = parted_box();
  constexpr double kTolerance = 1e-6;
  int iterations[2] = {0, 0};
  for (const bool parts : {false, true}) {
    BlockSystem system = elastic_like_system(9, box.data);
    if (parts) {
      system.pattern.set_parts(box.cut.offsets);
    }
    const Eigen::VectorXd b = random_vector(system.pattern.size(), 10);
    const int threads_before = omp_get_max_threads();
    std::vector<Eigen::VectorXd> answers;
    for (const int threads : {1, 2}) {
      omp_set_num_threads(threads);
      SolveReport report;
      answers.push_back(solve_within_tolerance(
          system, b, cg_options(Preconditioner::kSsor, kTolerance), &report));
      iterations[parts ? 1 : 0] = report.iterations;
    }
    omp_set_num_threads(threads_before);
    EXPECT_TRUE(answers[0] == answers[1]) << "parts " << parts;  // bit-identical
  }
  // The separator's vertices are swept last, which couples less at once: a few more iterations.
  EXPECT_LE(iterations[1], 1.25 * iterations[0]) << iterations[0] << " vs " << iterations[1];
}

/// x from zero, with `threads` OpenMP threads; the report into `report`.
Eigen::VectorXd solve_on_threads(const BlockSystem& system,
                                 const Eigen::VectorXd& b,
                                 const LinearSolverOptions& options,
                                 int threads,
                                 SolveReport& report) {
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(threads);
  const auto solver = make_system_solver(options, system.pattern);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  report = solver->solve(system.pattern, b, x, nullptr);
  omp_set_num_threads(threads_before);
  return x;
}

TEST(SystemSolver, SsorWithPartsAggregatesAndSingleSweepsLoadsTheSameOnAnyThreadCount) {
  // The solve's start on the threads: E's factorisation on one thread beside the diagonal
  // blocks and the single-precision copy on the others. The same answer to the bit at one and
  // two threads; and a singular diagonal block found wherever it lies, the solve then failing
  // with NaN rather than iterating.
  PartitionedOrder cut;
  BlockSystem system = parted_box_system(11, &cut);
  LinearSolverOptions options = cg_options(Preconditioner::kSsor, 1e-6);
  options.coarse_vertices = 32;
  options.single_precision_sweeps = true;
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 12);
  SolveReport one;
  SolveReport two;
  const Eigen::VectorXd x1 = solve_on_threads(system, b, options, 1, one);
  const Eigen::VectorXd x2 = solve_on_threads(system, b, options, 2, two);
  EXPECT_TRUE(one.converged);
  EXPECT_TRUE(x1 == x2);  // bit-identical

  // A vertex of the second part, so that on two threads it is not the first block taken.
  const int vertex = cut.offsets[1] + 3;
  system.pattern.set(system.pattern.vertex_block(vertex), Eigen::Matrix3d::Zero());
  for (const int threads : {1, 2}) {
    SolveReport report;
    const Eigen::VectorXd x = solve_on_threads(system, b, options, threads, report);
    EXPECT_FALSE(report.succeeded) << threads;
    EXPECT_TRUE(x.array().isNaN().all()) << threads;
  }
}

TEST(SystemSolver, SsorReadsTheDoublesBelowTheSingleSweepsTolerance) {
  // Asked for 1e-8 with single-precision sweeps, CG on the rounded sweeps broke down here after
  // 37 iterations with a residual of 0.52 (no tolerance below the rounding's effect can be
  // met). Below kSingleSweepsTolerance the solver reads the doubles: it converges, to the same
  // bits as a solve asked for double sweeps. At the floor it still reads the copy (the answer
  // differs from the doubles' in its last bits) and converges.
  const BlockSystem system = parted_box_system(11);
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 12);
  // One solve at `tolerance` with double sweeps asked, one with single: their reports and answers.
  struct Pair {
    SolveReport doubles, single;
    Eigen::VectorXd x_doubles, x_single;
  };
  const auto solve_both = [&](double tolerance) {
    LinearSolverOptions options = cg_options(Preconditioner::kSsor, tolerance);
    options.coarse_vertices = 32;
    Pair pair;
    pair.x_doubles = solve_on_threads(system, b, options, 1, pair.doubles);
    options.single_precision_sweeps = true;
    pair.x_single = solve_on_threads(system, b, options, 1, pair.single);
    return pair;
  };
  const Pair tight = solve_both(1e-8);
  EXPECT_TRUE(tight.single.converged);
  EXPECT_LT(tight.single.residual, 1e-6);
  EXPECT_TRUE(tight.x_single == tight.x_doubles);

  const Pair floor = solve_both(SsorConjugateGradientSolver::kSingleSweepsTolerance);
  EXPECT_TRUE(floor.single.converged);
  EXPECT_FALSE(floor.x_single == floor.x_doubles);
}

TEST(SystemSolver, SsorStartsFromTheGuessItIsGiven) {
  const BlockSystem system = elastic_like_system(5);
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 6);
  const Eigen::VectorXd exact = system.dense.ldlt().solve(b);
  const auto solver = make_system_solver(cg_options(Preconditioner::kSsor, 1e-6), system.pattern);
  Eigen::VectorXd x = exact;
  // The error is judged against |0 + x0|_A, the answer's own energy: the solve stops as soon as
  // its estimate has its window, the exact answer kept, not solved again.
  const Eigen::VectorXd no_offset = Eigen::VectorXd::Zero(b.size());
  const SolveReport report = solver->solve(system.pattern, b, x, no_offset.data());
  EXPECT_LE(report.iterations, EnergyErrorEstimate::kDelay);
  EXPECT_LT((x - exact).norm(), 1e-9 * exact.norm());
}

/// The box's system numbered for locality (reverse Cuthill-McKee), as the models number theirs.
BlockSystem local_elastic_system(int nx, int ny, int nz, unsigned seed, bool with_dense = true) {
  const TetMesh box = make_tet_mesh(test::box_tets(nx, ny, nz));
  const TetMesh local = renumbered(box, reverse_cuthill_mckee(box.tets(), box.num_vertices()));
  MeshData data;
  data.vertices = local.rest_positions();
  data.tetrahedra = local.tets();
  return elastic_like_system(seed, data, with_dense);
}

/// W (3N x 3G) of an aggregate assignment: each vertex's aggregate's three translations.
Eigen::MatrixXd translations(const std::vector<int>& aggregate_of, int aggregates) {
  Eigen::MatrixXd w =
      Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(aggregate_of.size()), 3 * aggregates);
  for (std::size_t v = 0; v < aggregate_of.size(); ++v) {
    w.block<3, 3>(3 * static_cast<Eigen::Index>(v), 3 * aggregate_of[v]).setIdentity();
  }
  return w;
}

TEST(CoarseSpace, GrowsConnectedAggregatesOfAboutTheTargetSize) {
  const BlockSystem system = local_elastic_system(12, 8, 6, 21);
  const BlockPattern& pattern = system.pattern;
  constexpr int kTarget = 32;
  const std::vector<int> aggregate_of = grow_aggregates(pattern, kTarget);
  const int aggregates = 1 + *std::max_element(aggregate_of.begin(), aggregate_of.end());
  std::vector<int> sizes(static_cast<std::size_t>(aggregates), 0);
  for (const int a : aggregate_of) {
    ++sizes[static_cast<std::size_t>(a)];
  }
  for (int g = 0; g < aggregates; ++g) {
    // Every id used, none below a quarter of the target.
    EXPECT_GE(sizes[static_cast<std::size_t>(g)], kTarget / 4) << "aggregate " << g;
    // Connected: a search from its first vertex inside it reaches all of it.
    const auto first = static_cast<int>(std::find(aggregate_of.begin(), aggregate_of.end(), g)
                                        - aggregate_of.begin());
    std::vector<int> stack{first};
    std::vector<bool> seen(aggregate_of.size(), false);
    seen[static_cast<std::size_t>(first)] = true;
    int reached = 0;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      ++reached;
      for (const int n : pattern.neighbours(v)) {
        if (aggregate_of[static_cast<std::size_t>(n)] == g && !seen[static_cast<std::size_t>(n)]) {
          seen[static_cast<std::size_t>(n)] = true;
          stack.push_back(n);
        }
      }
    }
    EXPECT_EQ(reached, sizes[static_cast<std::size_t>(g)]) << "aggregate " << g;
  }
  // About the target on average: 637 vertices in 32s make 20 aggregates.
  const double mean = static_cast<double>(aggregate_of.size()) / aggregates;
  EXPECT_GT(mean, 0.6 * kTarget);
  EXPECT_LT(mean, 1.6 * kTarget);
  // No target, or one beyond the vertex count: the whole body.
  for (const int whole : {0, pattern.num_vertices()}) {
    const std::vector<int> one = grow_aggregates(pattern, whole);
    EXPECT_EQ(*std::max_element(one.begin(), one.end()), 0);
  }
}

// CoarseSpace against dense products, for the aggregates `aggregate_of`.
void expect_coarse_space_matches_dense(const BlockSystem& system,
                                       const std::vector<int>& aggregate_of) {
  CoarseSpace coarse(system.pattern, aggregate_of);
  ASSERT_TRUE(coarse.load(system.pattern));
  const Eigen::MatrixXd w = translations(aggregate_of, coarse.num_aggregates());
  const Eigen::MatrixXd aw = system.dense * w;
  const Eigen::MatrixXd e = w.transpose() * aw;
  const double scale = e.norm();
  EXPECT_LT((Eigen::MatrixXd(coarse.coarse_matrix()) - e).norm(), 1e-13 * scale);
  // (A W)^T y, on two vertex ranges, made range by range as the solver's sweep makes it.
  const Eigen::VectorXd y = random_vector(system.pattern.size(), 23);
  const int n = system.pattern.num_vertices();
  const std::vector<int> ranges{0, n / 2, n};
  coarse.clear_restriction(ranges);
  for (std::size_t range = 0; range + 1 < ranges.size(); ++range) {
    double* slice = coarse.restriction_slice(ranges, ranges[range], ranges[range + 1]);
    for (int v = ranges[range]; v < ranges[range + 1]; ++v) {
      coarse.add_product(v, y.data() + 3 * v, slice);
    }
  }
  coarse.finish_restriction(ranges);
  EXPECT_LT((coarse.coarse() - aw.transpose() * y).norm(), 1e-12 * (aw.transpose() * y).norm());
  // W^T y.
  coarse.restrict_to_coarse(ranges, y.data());
  EXPECT_LT((coarse.coarse() - w.transpose() * y).norm(), 1e-12 * (w.transpose() * y).norm());
  // E^-1, then A W mu and U W mu (the blocks above the diagonal) vertex by vertex.
  const Eigen::VectorXd h = coarse.coarse();
  coarse.solve();
  const Eigen::VectorXd mu = coarse.coarse();
  EXPECT_LT((e * mu - h).norm(), 1e-10 * h.norm());
  Eigen::MatrixXd upper = system.dense.triangularView<Eigen::StrictlyUpper>();
  for (int v = 0; v < n; ++v) {  // the diagonal block is not U's
    upper.block<3, 3>(3 * v, 3 * v).setZero();
  }
  const Eigen::VectorXd full_product = aw * mu;
  const Eigen::VectorXd upper_product = upper * w * mu;
  for (int v = 0; v < n; ++v) {
    double out[3];
    coarse.product_at(v, /*upper=*/false, out);
    EXPECT_LT((Eigen::Vector3d(out[0], out[1], out[2]) - full_product.segment<3>(3 * v)).norm(),
              1e-10 * full_product.norm());
    coarse.product_at(v, /*upper=*/true, out);
    EXPECT_LT((Eigen::Vector3d(out[0], out[1], out[2]) - upper_product.segment<3>(3 * v)).norm(),
              1e-10 * full_product.norm());
    EXPECT_EQ(coarse.translation(v), coarse.coarse().data() + 3 * aggregate_of[v]);
  }
}

TEST(CoarseSpace, LoadsWTransposeAWAndItsProductsFromTheMatrix) {
  const BlockSystem system = local_elastic_system(8, 5, 4, 22);
  // Aggregates of 20 vertices make a small E (a simplicial factor), of 2 one past
  // kSupernodalFrom (a supernodal factor).
  for (const int target : {20, 2}) {
    SCOPED_TRACE("aggregates of " + std::to_string(target));
    const std::vector<int> aggregate_of = grow_aggregates(system.pattern, target);
    const int unknowns = 3 * (1 + *std::max_element(aggregate_of.begin(), aggregate_of.end()));
    EXPECT_EQ(unknowns >= CoarseSpace::kSupernodalFrom, target == 2) << unknowns << " unknowns";
    expect_coarse_space_matches_dense(system, aggregate_of);
  }
}

TEST(SystemSolver, SsorWithAggregatesMeetsTheToleranceAndLeavesNoResidualOnThem) {
  const BlockSystem system = local_elastic_system(12, 8, 6, 24);
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 25);
  LinearSolverOptions options = cg_options(Preconditioner::kSsor, 1e-6);
  options.coarse_vertices = 32;
  const Eigen::VectorXd x = solve_within_tolerance(system, b, options);
  // Deflation keeps every residual orthogonal to the coarse space: each aggregate's sum of
  // b - A x is round-off against b's (without the deflation it would be about the residual's
  // own size, |b| 1e-8 here).
  const std::vector<int> aggregate_of = grow_aggregates(system.pattern, 32);
  const Eigen::MatrixXd w =
      translations(aggregate_of, 1 + *std::max_element(aggregate_of.begin(), aggregate_of.end()));
  const Eigen::VectorXd residual = b - system.dense * x;
  EXPECT_LT((w.transpose() * residual).norm(), 1e-12 * (w.transpose() * b).norm());
}

TEST(SystemSolver, SsorInSinglePrecisionMeetsTheToleranceGiveOrTakeTheRounding) {
  // The sweeps read the blocks off the diagonal rounded to single precision (A'), while the
  // diagonal blocks, the start's residual and the coarse level keep A's doubles: CG corrects
  // the start (after the coarse level) by A'^-1 of A's residual, so the rounding touches only
  // that correction. The answer must be within the tolerance of A^-1 b, give or take at most
  // the rounding's whole effect on the answer, |A^-1 b - A'^-1 b|_A (5e-6 of it here, five times
  // the tolerance: the test would see a solve of A' alone), and take the iterations A's solve
  // takes, one more or fewer at most.
  const BlockSystem system = local_elastic_system(12, 8, 6, 24);
  const Eigen::VectorXd b = random_vector(system.pattern.size(), 28);
  LinearSolverOptions options = cg_options(Preconditioner::kSsor, 1e-6);
  options.coarse_vertices = 32;
  SolveReport in_double;
  const Eigen::VectorXd x_double = [&] {
    const auto solver = make_system_solver(options, system.pattern);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    in_double = solver->solve(system.pattern, b, x, nullptr);
    return x;
  }();
  options.single_precision_sweeps = true;
  const auto solver = make_system_solver(options, system.pattern);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  const SolveReport in_single = solver->solve(system.pattern, b, x, nullptr);

  Eigen::MatrixXd rounded = system.dense;
  for (Eigen::Index j = 0; j < rounded.cols(); ++j) {
    for (Eigen::Index i = 0; i < rounded.rows(); ++i) {
      if (i / 3 != j / 3) {
        rounded(i, j) = static_cast<float>(rounded(i, j));
      }
    }
  }
  const Eigen::VectorXd exact = system.dense.ldlt().solve(b);
  const double scale = energy_norm(system.dense, exact);
  const double rounding = energy_norm(system.dense, exact - rounded.ldlt().solve(b));
  const double error = energy_norm(system.dense, x - exact);
  SCOPED_TRACE(testing::Message() << "error " << error / scale << ", the rounding's effect "
                                  << rounding / scale << "; iterations " << in_double.iterations
                                  << " / " << in_single.iterations);
  EXPECT_TRUE(in_single.converged);
  EXPECT_GT(rounding, 2.0 * options.tolerance * scale);
  EXPECT_LT(error, 10.0 * options.tolerance * scale + rounding);
  EXPECT_NE(x, x_double);  // the single-precision copy is what the sweeps read
  EXPECT_LE(std::abs(in_single.iterations - in_double.iterations), 1);
}

TEST(SystemSolver, SsorWithAggregatesNeedsFewerIterationsAsTheMeshIsRefined) {
  // The same box at two resolutions (8x the vertices): the sweeps alone need more iterations on
  // the fine one (the smooth error they leave grows with the mesh: 34 -> 58 iterations when
  // written); with aggregates of 32 vertices the coarse level takes that error, and the
  // iterations hardly grow (19 -> 22).
  int iterations[2][2] = {};  // [fine][coarse level]
  for (const bool fine : {false, true}) {
    const BlockSystem system = fine ? local_elastic_system(24, 16, 12, 26, /*with_dense=*/false)
                                    : local_elastic_system(12, 8, 6, 26, /*with_dense=*/false);
    const Eigen::VectorXd b = random_vector(system.pattern.size(), 27);
    for (const int vertices : {0, 32}) {
      LinearSolverOptions options = cg_options(Preconditioner::kSsor, 1e-6);
      options.coarse_vertices = vertices;
      const auto solver = make_system_solver(options, system.pattern);
      Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
      const SolveReport report = solver->solve(system.pattern, b, x, nullptr);
      EXPECT_TRUE(report.converged);
      iterations[fine ? 1 : 0][vertices > 0 ? 1 : 0] = report.iterations;
    }
  }
  SCOPED_TRACE(testing::Message() << "coarse box " << iterations[0][0] << " / " << iterations[0][1]
                                  << ", fine box " << iterations[1][0] << " / " << iterations[1][1]
                                  << " iterations without / with aggregates");
  EXPECT_GT(iterations[1][0], 1.4 * iterations[0][0]);
  EXPECT_LT(iterations[1][1], 1.25 * iterations[0][1]);
  EXPECT_LT(iterations[1][1], 0.5 * iterations[1][0]);
}

TEST(GalerkinWarmStart, FindsASolutionLyingInTheSpanOfItsVectors) {
  const BlockSystem system = elastic_like_system(7);
  const Eigen::Index size = system.pattern.size();
  GalerkinWarmStart warm_start(size);
  const Eigen::VectorXd oldest = random_vector(size, 8);
  const Eigen::VectorXd older = random_vector(size, 9);
  const Eigen::VectorXd old = random_vector(size, 10);
  const Eigen::VectorXd newest = random_vector(size, 11);  // dropped: the guess stands for it
  for (const Eigen::VectorXd* v : {&oldest, &older, &old, &newest}) {
    warm_start.remember(*v);
  }
  const Eigen::VectorXd guess = random_vector(size, 12);
  const Eigen::VectorXd solution = 0.2 * guess - 0.7 * old + 1.5 * older + 0.1 * oldest;
  const Eigen::VectorXd b = system.dense * solution;
  Eigen::VectorXd x = guess;
  warm_start.improve(
      b, x,
      [&system](std::span<const Eigen::VectorXd* const> in, std::span<Eigen::VectorXd* const> out) {
        system.pattern.multiply_many(in, out);
      });
  EXPECT_LT((x - solution).norm(), 1e-9 * solution.norm());
}

TEST(GalerkinWarmStart, IsNoFartherFromTheSolutionThanTheGuessAndForgets) {
  const BlockSystem system = elastic_like_system(13);
  const Eigen::Index size = system.pattern.size();
  const Eigen::VectorXd b = random_vector(size, 14);
  const Eigen::VectorXd exact = system.dense.ldlt().solve(b);
  GalerkinWarmStart warm_start(size);
  for (unsigned seed = 15; seed < 19; ++seed) {
    warm_start.remember(exact + 0.1 * random_vector(size, seed));
  }
  const Eigen::VectorXd guess = exact + 0.1 * random_vector(size, 20);
  const auto multiply = [&system](std::span<const Eigen::VectorXd* const> in,
                                  std::span<Eigen::VectorXd* const> out) {
    system.pattern.multiply_many(in, out);
  };
  Eigen::VectorXd x = guess;
  warm_start.improve(b, x, multiply);
  // The A-norm projection onto the span: its error is at most the guess's (which is in it).
  EXPECT_LE(energy_norm(system.dense, x - exact), energy_norm(system.dense, guess - exact));
  EXPECT_NE(x, guess);

  warm_start.forget();
  x = guess;
  warm_start.improve(b, x, multiply);
  EXPECT_EQ(x, guess);  // nothing remembered: the guess is kept as it is
}

}  // namespace
}  // namespace softbench
