// The sparse LDLᵀ of the engine's cluster solves (dynamics/sparse_ldl.hpp) against dense
// algebra: solutions, pinned redundant rows, the fill limit, and the factorisation shared
// out among threads, which must give the serial factor bit for bit; the same for its LDU
// form (symmetric pattern, unsymmetric values: frictional clusters).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/random.hpp"
#include "dynamics/sparse_ldl.hpp"

namespace granflow {
namespace {

// Upper triangle of a dense symmetric matrix by columns, as SparseLdl takes it.
struct Upper {
  std::vector<int> start{0}, row;
  std::vector<double> value;
};

Upper upper(const Eigen::MatrixXd& a) {
  Upper u;
  for (int k = 0; k < a.cols(); ++k) {
    for (int i = 0; i <= k; ++i)
      if (a(i, k) != 0) {
        u.row.push_back(i);
        u.value.push_back(a(i, k));
      }
    u.start.push_back(int(u.row.size()));
  }
  return u;
}

// W = H·Hᵀ for a sparse random H: rows couple through shared columns, like contacts
// through shared grains.
Eigen::MatrixXd sparse_gram(int rows, int columns, std::uint64_t seed) {
  Rng rng(seed);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(rows, columns);
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < 3; ++k) h(r, int(rng.uniform(0, columns))) += rng.normal();
  return h * h.transpose();
}

TEST(SparseLdl, SolvesPositiveDefiniteSystem) {
  const Eigen::MatrixXd a = sparse_gram(60, 120, 3);
  const Upper u = upper(a);
  SparseLdl ldl;
  ASSERT_TRUE(ldl.factor(60, u.start, u.row, u.value, 1e-9, 1 << 20));
  EXPECT_EQ(ldl.pinned(), 0);
  Rng rng(4);
  Eigen::VectorXd b(60);
  for (int k = 0; k < 60; ++k) b(k) = rng.normal();
  std::vector<double> x(b.data(), b.data() + 60);
  ldl.solve(x);
  const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(x.data(), 60);
  EXPECT_LT((a * solution - b).norm(), 1e-10 * b.norm());
}

// A row that is a combination of others (a redundant contact): its unknown is pinned to 0
// and a consistent right-hand side is still solved exactly.
TEST(SparseLdl, PinsDependentUnknowns) {
  Rng rng(5);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(8, 12);
  for (int r = 0; r < 7; ++r)
    for (int k = 0; k < 3; ++k) h(r, int(rng.uniform(0, 12))) += rng.normal();
  h.row(7) = 0.5 * h.row(2) - 2.0 * h.row(5);
  const Eigen::MatrixXd a = h * h.transpose();
  Eigen::VectorXd x0(8);
  for (int k = 0; k < 8; ++k) x0(k) = rng.normal();
  const Eigen::VectorXd b = a * x0;
  const Upper u = upper(a);
  SparseLdl ldl;
  ASSERT_TRUE(ldl.factor(8, u.start, u.row, u.value, 1e-9, 1 << 20));
  EXPECT_EQ(ldl.pinned(), 1);
  std::vector<double> x(b.data(), b.data() + 8);
  ldl.solve(x);
  EXPECT_EQ(x[7], 0.0);
  const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(x.data(), 8);
  EXPECT_LT((a * solution - b).norm(), 1e-10 * b.norm());
}

TEST(SparseLdl, RefusesExcessiveFill) {
  const Eigen::MatrixXd a = sparse_gram(60, 40, 6);  // rows outnumber columns: dense fill
  const Upper u = upper(a);
  SparseLdl ldl;
  EXPECT_FALSE(ldl.factor(60, u.start, u.row, u.value, 1e-9, 100));
}

// Normal rows of the contacts of a 2D grid of grains (neighbours along x and y, and a
// diagonal in a fraction of the cells: more rows than velocities, some redundant), W = H·Hᵀ
// with random unit normals, reordered by approximate minimum degree as the engine orders large clusters: an
// elimination tree with many branches, like a percolating cluster's.
Upper grid_contacts(int side, double diagonals, std::uint64_t seed) {
  Rng rng(seed);
  std::vector<Eigen::Triplet<double>> h;
  int rows = 0;
  auto contact = [&](int a, int b) {
    const double angle = rng.uniform(0, 2 * M_PI);
    h.emplace_back(rows, 2 * a, std::cos(angle));
    h.emplace_back(rows, 2 * a + 1, std::sin(angle));
    h.emplace_back(rows, 2 * b, -std::cos(angle));
    h.emplace_back(rows, 2 * b + 1, -std::sin(angle));
    ++rows;
  };
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int g = y * side + x;
      if (x + 1 < side) contact(g, g + 1);
      if (y + 1 < side) contact(g, g + side);
      if (x + 1 < side && y + 1 < side && rng.uniform(0, 1) < diagonals) contact(g, g + side + 1);
    }
  Eigen::SparseMatrix<double> hm(rows, 2 * side * side);
  hm.setFromTriplets(h.begin(), h.end());
  const Eigen::SparseMatrix<double> w = hm * hm.transpose();
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
  Eigen::AMDOrdering<int>()(w, order);
  Eigen::SparseMatrix<double> pw;
  pw = w.twistedBy(order.inverse());
  Upper u;
  for (int k = 0; k < pw.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(pw, k); it; ++it)
      if (it.row() <= k) {
        u.row.push_back(int(it.row()));
        u.value.push_back(it.value());
      }
    u.start.push_back(int(u.row.size()));
  }
  return u;
}

// The factorisation shared out among threads by subtrees of the elimination tree gives the
// serial factor bit for bit (pinned rows included), and solves the system.
TEST(SparseLdl, ThreadsGiveTheSerialFactor) {
  const Upper u = grid_contacts(50, 0.125, 8);
  const int n = int(u.start.size()) - 1;
  ASSERT_GT(n, 4000);
  std::vector<double> b(n);
  Rng rng(9);
  for (double& v : b) v = rng.normal();
  std::vector<std::vector<double>> solutions;
  std::vector<int> pinned;
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    SparseLdl ldl;
    ASSERT_TRUE(ldl.factor(n, u.start, u.row, u.value, 1e-9, 1 << 26, threads));
    if (threads > 1) {
      EXPECT_GT(ldl.shared_rows(), n / 2);  // most rows computed in parallel
    }
    pinned.push_back(ldl.pinned());
    solutions.push_back(b);
    ldl.solve(solutions.back());
  }
  EXPECT_GT(pinned[0], 0);  // the diagonals make some rows redundant
  for (std::size_t t = 1; t < solutions.size(); ++t) {
    EXPECT_EQ(pinned[t], pinned[0]);
    EXPECT_EQ(solutions[t], solutions[0]);
  }
}

// Without redundant rows the threads' factor solves the system to round-off.
TEST(SparseLdl, ThreadsSolveTheSystem) {
  const Upper u = grid_contacts(50, 0, 10);
  const int n = int(u.start.size()) - 1;
  Rng rng(11);
  Eigen::SparseMatrix<double> a(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < n; ++k)
    for (int p = u.start[k]; p < u.start[k + 1]; ++p) {
      t.emplace_back(u.row[p], k, u.value[p]);
      if (u.row[p] != k) t.emplace_back(k, u.row[p], u.value[p]);
    }
  a.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd x0(n);
  for (int k = 0; k < n; ++k) x0(k) = rng.normal();
  const Eigen::VectorXd rhs = a * x0;
  SparseLdl ldl;
  ASSERT_TRUE(ldl.factor(n, u.start, u.row, u.value, 1e-9, 1 << 26, 2));
  EXPECT_GT(ldl.shared_rows(), n / 2);
  EXPECT_EQ(ldl.pinned(), 0);
  std::vector<double> x(rhs.data(), rhs.data() + n);
  ldl.solve(x);
  const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(x.data(), n);
  EXPECT_LT((a * solution - rhs).norm(), 1e-8 * rhs.norm());
}

// Both triangles of a dense matrix with a symmetric pattern, as the LDU form takes them:
// upper[p] = A(row[p], k), lower[p] = A(k, row[p]) for row[p] ≤ k.
struct Both {
  std::vector<int> start{0}, row;
  std::vector<double> upper, lower;
};

Both both(const Eigen::MatrixXd& a) {
  Both u;
  for (int k = 0; k < a.cols(); ++k) {
    for (int i = 0; i <= k; ++i)
      if (a(i, k) != 0 || a(k, i) != 0) {
        u.row.push_back(i);
        u.upper.push_back(a(i, k));
        u.lower.push_back(a(k, i));
      }
    u.start.push_back(int(u.row.size()));
  }
  return u;
}

// A frictional cluster's matrix: W = H·M⁻¹·Hᵀ over (normal, tangential) pairs of rows, then
// the tangential rows of "sliding" contacts replaced by P_t − sμ·P_n (zeros kept in the
// pattern, as the engine assembles them). Unsymmetric, with a symmetric pattern.
Eigen::MatrixXd sliding_gram(int contacts, int columns, double mu, std::uint64_t seed) {
  Rng rng(seed);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(2 * contacts, columns);
  for (int r = 0; r < 2 * contacts; ++r)
    for (int k = 0; k < 3; ++k) h(r, int(rng.uniform(0, columns))) += rng.normal();
  Eigen::MatrixXd a = h * h.transpose();
  for (int c = 0; c < contacts; ++c)
    if (rng.uniform(0, 1) < 0.4) {
      const int t = 2 * c + 1;
      const double s = rng.uniform(0, 1) < 0.5 ? 1.0 : -1.0;
      a.row(t).setZero();  // both() keeps the entries of column t: the pattern stays symmetric
      a(t, t) = 1;
      a(t, 2 * c) = -s * mu;
    }
  return a;
}

TEST(SparseLdu, SolvesUnsymmetricSystemWithSymmetricPattern) {
  for (std::uint64_t seed : {21u, 22u, 23u}) {
    SCOPED_TRACE(seed);
    const Eigen::MatrixXd a = sliding_gram(30, 100, 0.4, seed);
    ASSERT_GT((a - a.transpose()).cwiseAbs().maxCoeff(), 0.1);  // really unsymmetric
    const Both u = both(a);
    SparseLdl ldu;
    ASSERT_TRUE(ldu.factor(60, u.start, u.row, u.upper, u.lower, 1e-9, 1 << 20));
    EXPECT_EQ(ldu.pinned(), 0);
    Rng rng(seed + 100);
    Eigen::VectorXd b(60);
    for (int k = 0; k < 60; ++k) b(k) = rng.normal();
    std::vector<double> x(b.data(), b.data() + 60);
    ldu.solve(x);
    const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(x.data(), 60);
    const Eigen::VectorXd exact = a.fullPivLu().solve(b);
    EXPECT_LT((a * solution - b).norm(), 1e-10 * b.norm());
    EXPECT_LT((solution - exact).norm(), 1e-8 * exact.norm());
  }
}

// The same factor solves the transposed system (the cluster solves' left self-stresses).
TEST(SparseLdu, SolvesTransposedSystem) {
  for (std::uint64_t seed : {24u, 25u}) {
    SCOPED_TRACE(seed);
    const Eigen::MatrixXd a = sliding_gram(30, 100, 0.4, seed);
    const Both u = both(a);
    SparseLdl ldu;
    ASSERT_TRUE(ldu.factor(60, u.start, u.row, u.upper, u.lower, 1e-9, 1 << 20));
    Rng rng(seed + 100);
    Eigen::VectorXd b(60);
    for (int k = 0; k < 60; ++k) b(k) = rng.normal();
    std::vector<double> x(b.data(), b.data() + 60);
    ldu.solve_transposed(x);
    const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(x.data(), 60);
    EXPECT_LT((a.transpose() * solution - b).norm(), 1e-10 * b.norm());
    EXPECT_GT((a * solution - b).norm(), 1e-3 * b.norm());  // not the untransposed solve
  }
}

// On a symmetric matrix the LDU form is the LDLᵀ: the same solution bit for bit.
TEST(SparseLdu, SymmetricInputGivesTheLdlSolution) {
  const Eigen::MatrixXd a = sparse_gram(60, 120, 3);
  const Upper s = upper(a);
  const Both u = both(a);
  SparseLdl ldl, ldu;
  ASSERT_TRUE(ldl.factor(60, s.start, s.row, s.value, 1e-9, 1 << 20));
  ASSERT_TRUE(ldu.factor(60, u.start, u.row, u.upper, u.lower, 1e-9, 1 << 20));
  Rng rng(4);
  std::vector<double> x(60);
  for (double& v : x) v = rng.normal();
  std::vector<double> y = x;
  ldl.solve(x);
  ldu.solve(y);
  EXPECT_EQ(x, y);
}

// A redundant unknown is pinned to 0 and a consistent right-hand side still solved exactly.
TEST(SparseLdu, PinsDependentUnknowns) {
  Eigen::MatrixXd a = sliding_gram(6, 40, 0.4, 31);
  // Unknown 11 (a tangential row) made a combination of rows 2 and 5 and column likewise.
  a.row(11) = 0.5 * a.row(2) - 2.0 * a.row(5);
  a.col(11) = 0.5 * a.col(2) - 2.0 * a.col(5);
  Rng rng(32);
  Eigen::VectorXd x0(12);
  for (int k = 0; k < 12; ++k) x0(k) = rng.normal();
  x0(11) = 0;
  const Eigen::VectorXd b = a * x0;
  const Both u = both(a);
  SparseLdl ldu;
  ASSERT_TRUE(ldu.factor(12, u.start, u.row, u.upper, u.lower, 1e-9, 1 << 20));
  EXPECT_EQ(ldu.pinned(), 1);
  std::vector<double> x(b.data(), b.data() + 12);
  ldu.solve(x);
  EXPECT_EQ(x[11], 0.0);
  const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(x.data(), 12);
  EXPECT_LT((a * solution - b).norm(), 1e-9 * b.norm());
}

// Shared out among threads the LDU factor is the serial one, bit for bit, and solves the system.
TEST(SparseLdu, ThreadsGiveTheSerialFactor) {
  const Upper g = grid_contacts(50, 0, 12);
  const int n = int(g.start.size()) - 1;
  Both u;
  u.start = g.start;
  u.row = g.row;
  u.upper = g.value;
  u.lower = g.value;
  Rng rng(13);
  for (int k = 0; k < n; ++k)  // unsymmetric off the diagonal
    for (int p = u.start[k]; p < u.start[k + 1]; ++p) {
      if (u.row[p] != k) u.lower[p] *= 1 + 0.3 * rng.normal();
    }
  Eigen::SparseMatrix<double> a(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < n; ++k)
    for (int p = u.start[k]; p < u.start[k + 1]; ++p) {
      t.emplace_back(u.row[p], k, u.upper[p]);
      if (u.row[p] != k) t.emplace_back(k, u.row[p], u.lower[p]);
    }
  a.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd x0(n);
  for (int k = 0; k < n; ++k) x0(k) = rng.normal();
  const Eigen::VectorXd rhs = a * x0;
  std::vector<std::vector<double>> solutions;
  for (int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    SparseLdl ldu;
    ASSERT_TRUE(ldu.factor(n, u.start, u.row, u.upper, u.lower, 1e-9, 1 << 26, threads));
    if (threads > 1) {
      EXPECT_GT(ldu.shared_rows(), n / 2);
    }
    EXPECT_EQ(ldu.pinned(), 0);
    solutions.emplace_back(rhs.data(), rhs.data() + n);
    ldu.solve(solutions.back());
  }
  for (std::size_t k = 1; k < solutions.size(); ++k) EXPECT_EQ(solutions[k], solutions[0]);
  const Eigen::VectorXd solution = Eigen::Map<Eigen::VectorXd>(solutions[0].data(), n);
  EXPECT_LT((a * solution - rhs).norm(), 1e-8 * rhs.norm());
}

}  // namespace
}  // namespace granflow
