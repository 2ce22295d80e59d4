// Lemke's complementary pivoting (dynamics/lemke.hpp): the trivial q ≥ 0, positive definite problems
// against brute-force enumeration of the complementary bases, the frictional contact LCP (a copositive,
// rank-deficient matrix) with its Coulomb laws checked directly, in any units and degenerate (many
// q_i = 0, duplicated contacts), a problem on which Lemke cycles without the lexicographic rule, problems
// without a solution, the pivot limit and the scratch.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/random.hpp"
#include "dynamics/lemke.hpp"

namespace granflow {
namespace {

Eigen::MatrixXd normal_matrix(int rows, int cols, Rng& rng) {
  Eigen::MatrixXd a(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) a(i, j) = rng.normal();
  return a;
}

Eigen::VectorXd normal_vector(int n, Rng& rng) { return normal_matrix(n, 1, rng); }

// The scale the solver's acceptance is relative to: max|q| + max|M|·max|z|.
double scale(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& z) {
  const double z_max = z.size() ? z.cwiseAbs().maxCoeff() : 0.0;
  return q.cwiseAbs().maxCoeff() + M.cwiseAbs().maxCoeff() * z_max;
}

// z ≥ 0 exactly (the solver sets its roundings below 0 to 0), w = M·z + q ≥ 0 and zᵢ·wᵢ = 0 to `rel` of
// the scale (the products to rel·scale·max|z|: they grow as z²).
::testing::AssertionResult solves(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, const Eigen::VectorXd& z,
                                  double rel) {
  if (z.size() != q.size()) return ::testing::AssertionFailure() << "z has " << z.size() << " entries";
  const Eigen::VectorXd w = M * z + q;
  const double tol = rel * scale(M, q, z), z_max = z.cwiseAbs().maxCoeff();
  for (int i = 0; i < z.size(); ++i) {
    if (!(z(i) >= 0)) return ::testing::AssertionFailure() << "z(" << i << ") = " << z(i);
    if (!(w(i) >= -tol)) return ::testing::AssertionFailure() << "w(" << i << ") = " << w(i);
    if (!(std::abs(z(i) * w(i)) <= tol * z_max))
      return ::testing::AssertionFailure() << "z(" << i << ")·w(" << i << ") = " << z(i) * w(i);
  }
  return ::testing::AssertionSuccess();
}

// Every complementary basis in turn (S: where z may be positive), the first whose solution is
// nonnegative with w ≥ 0 off S. For a positive definite M that is the only solution.
bool brute_force(const Eigen::MatrixXd& M, const Eigen::VectorXd& q, Eigen::VectorXd& z) {
  const int n = int(q.size());
  const double tol = 1e-12 * (q.cwiseAbs().maxCoeff() + 1);
  for (std::uint32_t mask = 0; mask < (1u << n); ++mask) {
    std::vector<int> s;
    for (int i = 0; i < n; ++i)
      if (mask >> i & 1) s.push_back(i);
    Eigen::MatrixXd sub(s.size(), s.size());
    Eigen::VectorXd rhs(s.size());
    for (std::size_t a = 0; a < s.size(); ++a) {
      rhs(a) = -q(s[a]);
      for (std::size_t b = 0; b < s.size(); ++b) sub(a, b) = M(s[a], s[b]);
    }
    const Eigen::VectorXd zs = sub.llt().solve(rhs);
    z.setZero(n);
    for (std::size_t a = 0; a < s.size(); ++a) z(s[a]) = zs(a);
    const Eigen::VectorXd w = M * z + q;
    bool ok = true;
    for (int i = 0; i < n; ++i) ok = ok && z(i) >= -tol && ((mask >> i & 1) || w(i) >= -tol);
    if (ok) return true;
  }
  return false;
}

// The frictional contact LCP of m contacts with Delassus matrix W (2m × 2m: rows 2k, 2k + 1 the normal
// and tangential directions of contact k), normal velocities a, tangential velocities c, friction μ.
// Unknowns of contact k, at 4k…4k + 3: P_n, β+, β−, λ (P_t = β+ − β−, λ the sliding speed).
struct FrictionLcp {
  Eigen::MatrixXd M;
  Eigen::VectorXd q;
};

FrictionLcp friction_lcp(const Eigen::MatrixXd& W, const Eigen::VectorXd& a, const Eigen::VectorXd& c, double mu) {
  const int m = int(a.size());
  FrictionLcp f{Eigen::MatrixXd::Zero(4 * m, 4 * m), Eigen::VectorXd::Zero(4 * m)};
  for (int k = 0; k < m; ++k) {
    for (int j = 0; j < m; ++j) {
      for (int d = 0; d < 2; ++d) {  // rows of w_n and w_β+: (W·P)_n and (W·P)_t, P_t = β+ − β−
        f.M(4 * k + d, 4 * j) = W(2 * k + d, 2 * j);
        f.M(4 * k + d, 4 * j + 1) = W(2 * k + d, 2 * j + 1);
        f.M(4 * k + d, 4 * j + 2) = -W(2 * k + d, 2 * j + 1);
      }
      // w_β−: −(W·P)_t
      f.M(4 * k + 2, 4 * j) = -W(2 * k + 1, 2 * j);
      f.M(4 * k + 2, 4 * j + 1) = -W(2 * k + 1, 2 * j + 1);
      f.M(4 * k + 2, 4 * j + 2) = W(2 * k + 1, 2 * j + 1);
    }
    f.M(4 * k + 1, 4 * k + 3) = 1;
    f.M(4 * k + 2, 4 * k + 3) = 1;
    f.M(4 * k + 3, 4 * k) = mu;
    f.M(4 * k + 3, 4 * k + 1) = -1;
    f.M(4 * k + 3, 4 * k + 2) = -1;
    f.q(4 * k) = a(k);
    f.q(4 * k + 1) = c(k);
    f.q(4 * k + 2) = -c(k);
  }
  return f;
}

// Coulomb's law contact by contact, to `rel` of the scale: |P_t| ≤ μP_n; sticking (λ = 0) has no
// tangential velocity u_t = (W·P)_t + c; sliding has P_t = −μ·P_n·sign(u_t).
void expect_coulomb(const FrictionLcp& f, const Eigen::MatrixXd& W, const Eigen::VectorXd& c, double mu,
                    const Eigen::VectorXd& z, double rel) {
  const int m = int(c.size());
  const double tol = rel * scale(f.M, f.q, z);
  Eigen::VectorXd P(2 * m);
  for (int k = 0; k < m; ++k) {
    P(2 * k) = z(4 * k);
    P(2 * k + 1) = z(4 * k + 1) - z(4 * k + 2);
  }
  const Eigen::VectorXd u = W * P;
  for (int k = 0; k < m; ++k) {
    const double p_n = P(2 * k), p_t = P(2 * k + 1), lambda = z(4 * k + 3), u_t = u(2 * k + 1) + c(k);
    EXPECT_LE(std::abs(p_t), mu * p_n + tol) << "contact " << k;
    if (lambda <= tol) {
      EXPECT_LE(std::abs(u_t), 2 * tol) << "sticking contact " << k << " slides";
    }
    if (std::abs(u_t) > 1e-6 * scale(f.M, f.q, z)) {
      EXPECT_NEAR(p_t, -mu * p_n * (u_t > 0 ? 1 : -1), tol) << "sliding contact " << k;
    }
  }
}

TEST(Lemke, NonnegativeQIsSolvedByZero) {
  Rng rng(1);
  const Eigen::MatrixXd M = normal_matrix(5, 5, rng);
  Eigen::VectorXd q(5);
  q << 0.5, 0, 2, 0, 1e-3;
  Lemke lemke;
  Eigen::VectorXd z = Eigen::VectorXd::Constant(3, 7.0);
  ASSERT_TRUE(lemke.solve(M, q, z, 100));
  EXPECT_EQ(lemke.pivots(), 0);
  EXPECT_EQ(z, Eigen::VectorXd::Zero(5));
}

TEST(Lemke, PositiveDefiniteMatchesEnumeration) {
  Lemke lemke;  // one object throughout: its scratch is reused across sizes
  for (int n = 1; n <= 12; ++n)
    for (std::uint64_t seed = 0; seed < 5; ++seed) {
      Rng rng(100 * n + seed);
      const Eigen::MatrixXd A = normal_matrix(n, n, rng);
      const Eigen::MatrixXd M = A.transpose() * A + 0.1 * Eigen::MatrixXd::Identity(n, n);
      const Eigen::VectorXd q = normal_vector(n, rng);
      Eigen::VectorXd expected;
      ASSERT_TRUE(brute_force(M, q, expected));
      Eigen::VectorXd z;
      ASSERT_TRUE(lemke.solve(M, q, z, 10 * n)) << "n " << n << " seed " << seed;
      EXPECT_LE((z - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff())
          << "n " << n << " seed " << seed << "\nz " << z.transpose() << "\nexpected " << expected.transpose();
      EXPECT_TRUE(solves(M, q, z, 1e-9));
    }
}

// Contact velocities of a motion v of the degrees of freedom, (a, c) = Hᵀv (normal and
// tangential per contact), plus a separation in [0, 1) on about 30 % of the normals.
void motion_velocities(const Eigen::MatrixXd& H, Rng& rng, Eigen::VectorXd& a, Eigen::VectorXd& c) {
  const int m = int(H.cols()) / 2;
  const Eigen::VectorXd u = H.transpose() * normal_vector(int(H.rows()), rng);
  a.resize(m);
  c.resize(m);
  for (int k = 0; k < m; ++k) {
    a(k) = u(2 * k) + (rng.uniform() < 0.3 ? rng.uniform(0, 1) : 0.0);
    c(k) = u(2 * k + 1);
  }
}

// W = HᵀH with H of fewer rows than 2m: positive semi-definite and singular, as the Delassus matrix of
// more contacts than degrees of freedom. The velocities are those of a motion v of the degrees of freedom,
// (a, c) = Hᵀv, plus a separation g ≥ 0 on some normals: that is where Lemke is known to reach a solution
// (q in the dual of the homogeneous problem's solutions, whose P lie in the kernel of H). With (a, c)
// drawn freely and W singular the LCP can have no solution at all (m = 1, W = 0, a < 0).
TEST(Lemke, FrictionalContactsSatisfyCoulomb) {
  const double mus[] = {0.1, 0.4, 1.0};
  Lemke lemke;
  int negative = 0, sliding = 0, sticking = 0;
  for (int m = 1; m <= 10; ++m)
    for (int trial = 0; trial < 30; ++trial) {
      Rng rng(1000 * m + trial);
      const double mu = mus[trial % 3];
      const Eigen::MatrixXd H = normal_matrix(std::max(1, 2 * m - 2), 2 * m, rng);
      const Eigen::MatrixXd W = H.transpose() * H;
      Eigen::VectorXd a, c;
      motion_velocities(H, rng, a, c);
      negative += int((a.array() < 0).count());
      const FrictionLcp f = friction_lcp(W, a, c, mu);
      Eigen::VectorXd z;
      ASSERT_TRUE(lemke.solve(f.M, f.q, z, 40 * m)) << "m " << m << " trial " << trial;
      EXPECT_TRUE(solves(f.M, f.q, z, 1e-9)) << "m " << m << " trial " << trial;
      expect_coulomb(f, W, c, mu, z, 1e-9);
      for (int k = 0; k < m; ++k) {
        sliding += z(4 * k + 3) > 1e-6 && z(4 * k) > 1e-6;
        sticking += z(4 * k + 3) == 0 && z(4 * k) > 1e-6;
      }
    }
  // The draws must exercise what is checked: approaching, sliding and sticking contacts.
  EXPECT_GT(negative, 300);
  EXPECT_GT(sliding, 100);
  EXPECT_GT(sticking, 100);
}

// A resting packing hit at one contact: c = 0, a = 0 except one negative entry and a few positive ones,
// and duplicated contacts (identical rows and columns of M, identical q entries, the hit contact's too,
// so the very first pivot is a tie). About a fifth of the ratio tests have tied rows, at θ = 0 or between
// duplicates. The velocities are (a, c) = Hᵀe₀ + g with g ≥ 0, so that a solution exists: H's first row
// is 0 on tangents and ≤ 0 on normals but the hit one's.
TEST(Lemke, DegenerateFrictionTerminates) {
  Lemke lemke;
  int ties = 0;
  for (int m = 2; m <= 12; ++m)
    for (int trial = 0; trial < 10; ++trial) {
      Rng rng(5000 * m + trial);
      const double mu = trial % 2 ? 0.5 : 1.0;
      Eigen::MatrixXd H = normal_matrix(2 * m - 2, 2 * m, rng);
      const int hit = int(rng.uniform(0, m));
      for (int k = 0; k < m; ++k) {
        H(0, 2 * k) = k == hit ? -1.0 : -std::abs(H(0, 2 * k));
        H(0, 2 * k + 1) = 0;
      }
      std::vector<int> copy_of(m, -1);  // contact k duplicates contact copy_of[k]
      for (int k = 1; k < m; ++k)
        if (rng.uniform() < 0.4) {
          copy_of[k] = int(rng.uniform(0, k));
          if (copy_of[copy_of[k]] >= 0) copy_of[k] = copy_of[copy_of[k]];  // the original, not a copy
          if (k == hit) copy_of[k] = -1;
          if (copy_of[k] >= 0) H.middleCols(2 * k, 2) = H.middleCols(2 * copy_of[k], 2);
        }
      const Eigen::MatrixXd W = H.transpose() * H;
      Eigen::VectorXd a = Eigen::VectorXd::Zero(m), c = Eigen::VectorXd::Zero(m);
      for (int k = 0; k < m; ++k) {
        const int origin = copy_of[k] >= 0 ? copy_of[k] : k;
        if (origin == hit) a(k) = -1.0;
        else if (rng.uniform() < 0.2) a(k) = rng.uniform(0, 1);
      }
      ties += std::count(a.data(), a.data() + m, -1.0) > 1;
      const FrictionLcp f = friction_lcp(W, a, c, mu);
      const int n = 4 * m;
      Eigen::VectorXd z;
      ASSERT_TRUE(lemke.solve(f.M, f.q, z, 10 * n)) << "m " << m << " trial " << trial << ", pivots " << lemke.pivots();
      EXPECT_TRUE(solves(f.M, f.q, z, 1e-9)) << "m " << m << " trial " << trial;
      expect_coulomb(f, W, c, mu, z, 1e-9);
    }
  EXPECT_GT(ties, 5);  // hit contacts duplicated: ties in the first pivot
}

// The friction LCP in other units: W·s², (a, c)·s for s from 10⁻³ to 10³ (impulses P/s, sliding speed
// λ·s), next to the unit entries of the friction rows, as SI units give for grains of a few grams
// (W ~ 10³) or of a milligram (W ~ 10⁶). Duplicated contacts make it degenerate as well. The solution
// must be that of the problem in s = 1 units, (s·P, λ/s), each row to its own precision: a tolerance
// relative to the largest entries would let the small rows go.
TEST(Lemke, FrictionInAnyUnits) {
  Lemke lemke;
  for (int power = -3; power <= 3; ++power)
    for (int m = 2; m <= 10; m += 2)
      for (int trial = 0; trial < 10; ++trial) {
        Rng rng(10000 * (power + 5) + 100 * m + trial);
        const double s = std::pow(10.0, power), mu = trial % 2 ? 0.3 : 0.8;
        Eigen::MatrixXd H = normal_matrix(int(rng.uniform(1, 2 * m)), 2 * m, rng);
        for (int k = 1; k < m; ++k)
          if (rng.uniform() < 0.2) H.middleCols(2 * k, 2) = H.middleCols(2 * int(rng.uniform(0, k)), 2);
        const Eigen::MatrixXd W = H.transpose() * H;
        Eigen::VectorXd a, c;
        motion_velocities(H, rng, a, c);
        const FrictionLcp f = friction_lcp(s * s * W, s * a, s * c, mu);
        Eigen::VectorXd z;
        ASSERT_TRUE(lemke.solve(f.M, f.q, z, 40 * m)) << "s " << s << " m " << m << " trial " << trial;
        EXPECT_TRUE(solves(f.M, f.q, z, 1e-9)) << "s " << s << " m " << m << " trial " << trial;
        Eigen::VectorXd unit = z;
        for (int k = 0; k < m; ++k) {
          unit.segment(4 * k, 3) *= s;
          unit(4 * k + 3) /= s;
        }
        const FrictionLcp f1 = friction_lcp(W, a, c, mu);
        EXPECT_TRUE(solves(f1.M, f1.q, unit, 1e-9)) << "in units s = 1: s " << s << " m " << m << " trial " << trial;
        expect_coulomb(f1, W, c, mu, unit, 1e-9);
      }
}

// Lemke cycles on this problem when ties of the ratio test go to the first tied row, the last, or the
// largest pivot (found by a search over small integer problems, and confirmed in exact rational
// arithmetic); the lexicographic rule reaches the solution in 9 pivots. Entries ±1 and 0: equilibration
// leaves the problem as it is, so that the path is the one of d = (1, …, 1).
TEST(Lemke, LexicographicRuleAvoidsCycling) {
  Eigen::MatrixXd M(5, 5);
  M << 1, 1, 0, 0, 0,     //
      -1, -1, -1, 1, -1,  //
      -1, 0, 1, 1, 0,     //
      -1, -1, 1, 1, 1,    //
      1, 0, 0, 1, 0;
  Eigen::VectorXd q(5), expected(5);
  q << -1, 0, -1, -1, -1;
  expected << 1, 0, 0, 2, 0;
  Lemke lemke;
  Eigen::VectorXd z;
  ASSERT_TRUE(lemke.solve(M, q, z, 100));
  EXPECT_EQ(lemke.pivots(), 9);
  EXPECT_LE((z - expected).cwiseAbs().maxCoeff(), 1e-12) << z.transpose();
}

// w = −z − 1 < 0 for every z ≥ 0; and w₁ + w₂ = −2 whatever z for a singular positive semi-definite M,
// where Lemke ends on a secondary ray.
TEST(Lemke, InfeasibleProblemsFail) {
  Lemke lemke;
  Eigen::VectorXd z;
  EXPECT_FALSE(lemke.solve(Eigen::MatrixXd::Constant(1, 1, -1.0), Eigen::VectorXd::Constant(1, -1.0), z, 100));
  Eigen::MatrixXd M(2, 2);
  M << 1, -1, -1, 1;
  EXPECT_FALSE(lemke.solve(M, Eigen::VectorXd::Constant(2, -1.0), z, 100));
  EXPECT_LE(lemke.pivots(), 3);
}

// A NaN in M or q reaches the polished z; the checks must refuse it rather than return it as a solution.
TEST(Lemke, NonFiniteInputFails) {
  Rng rng(5);
  const Eigen::MatrixXd A = normal_matrix(4, 4, rng);
  const Eigen::MatrixXd M = A.transpose() * A + 0.1 * Eigen::MatrixXd::Identity(4, 4);
  const Eigen::VectorXd q = -Eigen::VectorXd::Ones(4);
  Lemke lemke;
  Eigen::VectorXd z;
  for (int i = 0; i < 4; ++i) {
    Eigen::MatrixXd bad_M = M;
    bad_M(i, i) = std::nan("");
    EXPECT_FALSE(lemke.solve(bad_M, q, z, 100)) << "NaN at M(" << i << ", " << i << "), z " << z.transpose();
    Eigen::VectorXd bad_q = q;
    bad_q(i) = std::nan("");
    EXPECT_FALSE(lemke.solve(M, bad_q, z, 100)) << "NaN at q(" << i << "), z " << z.transpose();
  }
}

TEST(Lemke, PivotLimitFails) {
  Rng rng(7);
  const Eigen::MatrixXd A = normal_matrix(8, 8, rng);
  const Eigen::MatrixXd M = A.transpose() * A + 0.1 * Eigen::MatrixXd::Identity(8, 8);
  const Eigen::VectorXd q = -Eigen::VectorXd::LinSpaced(8, 1.0, 2.0);  // all negative: many pivots
  Lemke lemke;
  Eigen::VectorXd z;
  ASSERT_TRUE(lemke.solve(M, q, z, 100));
  const int needed = lemke.pivots();
  ASSERT_GT(needed, 2);
  EXPECT_FALSE(lemke.solve(M, q, z, 1));
  EXPECT_EQ(lemke.pivots(), 1);
  EXPECT_FALSE(lemke.solve(M, q, z, needed - 1));
  EXPECT_TRUE(lemke.solve(M, q, z, needed));
  EXPECT_EQ(lemke.pivots(), needed);
}

TEST(Lemke, KeepsScratch) {
  Rng rng(9);
  const Eigen::MatrixXd A = normal_matrix(10, 10, rng);
  const Eigen::MatrixXd M = A.transpose() * A + 0.1 * Eigen::MatrixXd::Identity(10, 10);
  const Eigen::VectorXd q = normal_vector(10, rng) - Eigen::VectorXd::Constant(10, 1.0);
  Lemke lemke;
  EXPECT_EQ(lemke.bytes(), 0u);
  Eigen::VectorXd z;
  ASSERT_TRUE(lemke.solve(M, q, z, 100));
  EXPECT_GE(lemke.bytes(), 10u * 10u * sizeof(double));
}

}  // namespace
}  // namespace granflow
