#pragma once
// An independent reference for the one-step contact problem of a few disks: the problem
// (Delassus matrix W, free contact velocities u⁻, targets b_n, b_t, μ) built here from
// contact-point velocities, independently of the engine's formulas; the largest violation
// of each contact law by a candidate impulse vector (check_laws); and every admissible
// solution, found by enumerating the contact states (brute_force).
//
// Frame of contact k = (i, j), i < j: n̂ = (r_i − r_j)/|r_i − r_j|, t̂ = ẑ × n̂; P = (P_n, P_t)
// acts on i at its contact point (and −P on j), u = relative velocity of the two surface
// points facing each other. After the step u⁺ = u⁻ + W·P. The laws (lib/dynamics/engine.hpp):
//   normal:     P_n ≥ 0, u_n⁺ ≥ b_n, P_n·(u_n⁺ − b_n) = 0, with b_n by Moreau's activation:
//               touching or predicted to touch (g ≤ 0 or g + dt·u_n⁻ ≤ 0): −e·min(u_n⁻, 0);
//               otherwise −g/dt (the gap may close, never below zero);
//   tangential: |P_t| ≤ μP_n; sticking (|P_t| < μP_n) ⇒ u_t⁺ = b_t = e_t·u_t⁻;
//               sliding (u_t⁺ ≠ b_t) ⇒ P_t = −μP_n·sign(u_t⁺ − b_t).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/vec.hpp"
#include "dynamics/grains.hpp"

namespace granflow::test {

struct ContactProblem {
  std::vector<std::pair<int, int>> pairs;  // grains i < j of each contact row pair
  Eigen::MatrixXd H;                       // contact velocities (u_n, u_t per pair) of grain velocities
  Eigen::VectorXd inv_mass;                // (1/m, 1/m, 1/I) per grain, 0 for a fixed grain
  Eigen::VectorXd q0;                      // (v_x, v_y, ω) per grain before the step
  Eigen::MatrixXd W;                       // H·M⁻¹·Hᵀ
  Eigen::VectorXd u0;                      // H·q0: (u_n⁻, u_t⁻) per pair
  Eigen::VectorXd bn, bt;                  // targets per pair
  double mu = 0;
  int contacts() const { return int(pairs.size()); }
  // The largest velocity in the problem: the unit of check_laws' violations.
  double velocity_scale() const {
    double v = 0;
    if (u0.size()) v = std::max({u0.cwiseAbs().maxCoeff(), bn.cwiseAbs().maxCoeff(), bt.cwiseAbs().maxCoeff()});
    return v > 0 ? v : 1.0;
  }
  // Grain velocities after the impulses P.
  Eigen::VectorXd velocity(const Eigen::VectorXd& P) const { return q0 + inv_mass.asDiagonal() * (H.transpose() * P); }
};

// Every pair of grains closer than `alert` (gap), as the engine's candidates (no periodic
// images: the clusters are far from the box's edges). No gravity.
inline ContactProblem contact_problem(const GrainState& s, const Material& mat, double dt, double alert) {
  const int n = int(s.size());
  ContactProblem p;
  p.mu = mat.friction;
  std::vector<Vec2> normal;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (s.fixed[i] && s.fixed[j]) continue;
      const Vec2 d = s.position[i] - s.position[j];
      if (d.norm() - s.radius[i] - s.radius[j] < alert) {
        p.pairs.emplace_back(i, j);
        normal.push_back(d.normalized());
      }
    }
  const int c = p.contacts();
  // Relative velocity of the two surface points facing each other, r_i − R_i n̂ and r_j + R_j n̂.
  auto contact_velocity = [&](const Eigen::VectorXd& q, int k) {
    const auto [i, j] = p.pairs[k];
    auto at = [&](int g, const Vec2& arm) {
      const Eigen::Vector3d v(q(3 * g), q(3 * g + 1), 0), w(0, 0, q(3 * g + 2));
      const Eigen::Vector3d u = v + w.cross(Eigen::Vector3d(arm.x(), arm.y(), 0));
      return Vec2(u.x(), u.y());
    };
    const Vec2 u = at(i, -s.radius[i] * normal[k]) - at(j, s.radius[j] * normal[k]);
    const Vec2 t(-normal[k].y(), normal[k].x());
    return Eigen::Vector2d(u.dot(normal[k]), u.dot(t));
  };
  p.H.resize(2 * c, 3 * n);
  for (int col = 0; col < 3 * n; ++col)
    for (int k = 0; k < c; ++k) p.H.block<2, 1>(2 * k, col) = contact_velocity(Eigen::VectorXd::Unit(3 * n, col), k);
  p.q0.resize(3 * n);
  p.inv_mass.resize(3 * n);
  for (int g = 0; g < n; ++g) {
    p.q0.segment<3>(3 * g) << s.velocity[g].x(), s.velocity[g].y(), s.angular_velocity[g];
    const double w = s.fixed[g] ? 0.0 : 1 / s.mass[g];
    p.inv_mass.segment<3>(3 * g) << w, w, 2 * w / (s.radius[g] * s.radius[g]);
  }
  p.W = p.H * p.inv_mass.asDiagonal() * p.H.transpose();
  p.u0 = p.H * p.q0;
  p.bn.resize(c);
  p.bt.resize(c);
  for (int k = 0; k < c; ++k) {
    const auto [i, j] = p.pairs[k];
    const double gap = (s.position[i] - s.position[j]).norm() - s.radius[i] - s.radius[j];
    const double un = p.u0(2 * k);
    p.bn(k) = (gap <= 0 || gap + dt * un <= 0) ? (un < 0 ? -mat.restitution * un : 0.0) : -gap / dt;
    p.bt(k) = mat.tangential_restitution * p.u0(2 * k + 1);
  }
  return p;
}

// Largest violation of each law over the contacts, in units of the problem's velocity
// scale; impulses enter as the velocity change they cause at their own contact (P·W_kk).
// Each measure is free of thresholds: it is zero for an exact solution and grows with
// the distance from one.
struct LawViolation {
  double nonnegative = 0;      // (a) max(0, −P_n)·W_nn
  double bound = 0;            // (b) max(0, b_n − u_n⁺)
  double complementarity = 0;  // (c) max(0, min(P_n·W_nn, u_n⁺ − b_n)): impulse and gap at once
  double cone = 0;             // (d) max(0, |P_t| − μP_n)·W_tt
  double stick = 0;  // (e) max(0, min((μP_n − |P_t|)·W_tt, |u_t⁺ − b_t|)): inside the cone yet slipping
  double slide = 0;  // (f) max(0, min(P_t·sign(u_t⁺ − b_t)·W_tt, |u_t⁺ − b_t|)): pushing along the slip
  double max() const { return std::max({nonnegative, bound, complementarity, cone, stick, slide}); }
};

inline LawViolation check_laws(const ContactProblem& p, const Eigen::VectorXd& P) {
  const Eigen::VectorXd u = p.u0 + p.W * P;
  const double scale = p.velocity_scale();
  LawViolation v;
  auto raise = [](double& worst, double x) { worst = std::max(worst, x); };
  for (int k = 0; k < p.contacts(); ++k) {
    const int rn = 2 * k, rt = 2 * k + 1;
    const double wn = p.W(rn, rn), wt = p.W(rt, rt);
    const double pn = P(rn), pt = P(rt);
    const double gap = u(rn) - p.bn(k), slip = u(rt) - p.bt(k);
    raise(v.nonnegative, -pn * wn / scale);
    raise(v.bound, -gap / scale);
    raise(v.complementarity, std::min(pn * wn, gap) / scale);
    raise(v.cone, (std::fabs(pt) - p.mu * pn) * wt / scale);
    raise(v.stick, std::min((p.mu * pn - std::fabs(pt)) * wt, std::fabs(slip)) / scale);
    const double along = slip > 0 ? pt : slip < 0 ? -pt : 0.0;
    raise(v.slide, std::min(along * wt, std::fabs(slip)) / scale);
  }
  return v;
}

// State of a contact in an enumerated solution.
enum class ContactState { off, stick, slide_plus, slide_minus };  // slide±: P_t = ±μP_n

struct Reference {
  struct Solution {
    Eigen::VectorXd impulse;   // (P_n, P_t) per pair
    Eigen::VectorXd velocity;  // (v_x, v_y, ω) per grain after the step
    std::vector<ContactState> state;
  };
  ContactProblem problem;
  std::vector<std::pair<int, int>> pairs;  // = problem.pairs
  std::vector<Solution> solutions;         // the distinct admissible solutions found
  // More contact rows than independent contact velocities (W singular): the solutions may
  // then form a continuum, of which the enumeration finds the vertices only.
  bool redundant = false;
  std::int64_t systems = 0;  // linear systems solved
};

// Contacts the enumeration accepts: 4^c assignments, each a system of up to 2c unknowns in
// storage of fixed size (no allocation in the loop).
inline constexpr int kMaxBruteForceContacts = 8;

// Admissible: every law of check_laws within this (relative) bound. The vertex solutions
// come from small dense solves, exact to round-off times the systems' condition.
inline constexpr double kAdmissible = 1e-10;

// Enumerates the contact states (off, stick, slide with P_t = +μP_n, slide with P_t = −μP_n;
// off and on without friction). Each assignment fixes a square linear system in the unknown
// impulses only (P_n of the contacts on, P_t of those sticking; sliding ones have
// P_t = ±μP_n, off ones P = 0): u_n⁺ = b_n on the contacts on, u_t⁺ = b_t on the sticking
// ones. Regular systems whose solution obeys every law are kept, once each.
inline Reference brute_force(const GrainState& s, const Material& mat, double dt, double alert) {
  Reference ref;
  ref.problem = contact_problem(s, mat, dt, alert);
  const ContactProblem& p = ref.problem;
  ref.pairs = p.pairs;
  const int c = p.contacts();
  if (c == 0) return ref;
  if (c > kMaxBruteForceContacts) throw std::invalid_argument("brute_force: too many contacts");
  ref.redundant = Eigen::FullPivLU<Eigen::MatrixXd>(p.H).rank() < 2 * c;
  const bool friction = p.mu > 0;
  const double scale = p.velocity_scale();
  const int kinds = friction ? 4 : 2;
  std::int64_t combos = 1;
  for (int k = 0; k < c; ++k) combos *= kinds;
  std::vector<ContactState> state(c);
  constexpr int kRows = 2 * kMaxBruteForceContacts;
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kRows, kRows>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kRows, 1>;
  std::vector<int> column_row, equation_row;  // per unknown: its row of P, and its equation's
  column_row.reserve(kRows);
  equation_row.reserve(kRows);
  Matrix WG(2 * c, 2 * c), A;
  Vector b;
  Eigen::VectorXd P(2 * c);
  for (std::int64_t code = 0; code < combos; ++code) {
    column_row.clear();
    equation_row.clear();
    std::int64_t rest = code;
    for (int k = 0; k < c; ++k, rest /= kinds) {
      const int digit = int(rest % kinds);
      state[k] = digit == 0                ? ContactState::off
                 : !friction || digit == 1 ? ContactState::stick
                 : digit == 2              ? ContactState::slide_plus
                                           : ContactState::slide_minus;
      if (state[k] == ContactState::off) continue;
      const int rn = 2 * k, rt = 2 * k + 1;
      // Column of P_n: W·(effect of a unit P_n, with P_t = ±μP_n when sliding).
      const double slope = state[k] == ContactState::slide_plus    ? p.mu
                           : state[k] == ContactState::slide_minus ? -p.mu
                                                                   : 0.0;
      WG.col(int(column_row.size())) = p.W.col(rn) + slope * p.W.col(rt);
      column_row.push_back(rn);
      equation_row.push_back(rn);
      if (friction && state[k] == ContactState::stick) {
        WG.col(int(column_row.size())) = p.W.col(rt);
        column_row.push_back(rt);
        equation_row.push_back(rt);
      }
    }
    const int m = int(column_row.size());
    P.setZero();
    if (m > 0) {
      A.resize(m, m);
      b.resize(m);
      for (int e = 0; e < m; ++e) {
        const int row = equation_row[e];
        for (int u = 0; u < m; ++u) A(e, u) = WG(row, u);
        b(e) = (row % 2 == 0 ? p.bn(row / 2) : p.bt(row / 2)) - p.u0(row);
      }
      ++ref.systems;
      const Eigen::FullPivLU<Matrix> lu(A);
      if (!lu.isInvertible()) continue;
      const Vector x = lu.solve(b);
      for (int u = 0; u < m; ++u) P(column_row[u]) = x(u);
      // Most assignments fail P_n ≥ 0 or |P_t| ≤ μP_n, seen without computing u⁺: the same
      // measures as check_laws' (a) and (d), so the set kept is the same, found sooner.
      bool possible = true;
      for (int k = 0; k < c && possible; ++k) {
        if (state[k] == ContactState::off) continue;
        const int rn = 2 * k, rt = 2 * k + 1;
        if (state[k] == ContactState::slide_plus) P(rt) = p.mu * P(rn);
        if (state[k] == ContactState::slide_minus) P(rt) = -p.mu * P(rn);
        possible = -P(rn) * p.W(rn, rn) <= kAdmissible * scale &&
                   (std::fabs(P(rt)) - p.mu * P(rn)) * p.W(rt, rt) <= kAdmissible * scale;
      }
      if (!possible) continue;
    }
    if (check_laws(p, P).max() > kAdmissible) continue;
    bool seen = false;
    for (const auto& f : ref.solutions)
      seen = seen || (f.impulse - P).cwiseAbs().maxCoeff() <=
                         1e-9 * std::max(f.impulse.cwiseAbs().maxCoeff(), P.cwiseAbs().maxCoeff());
    if (!seen) ref.solutions.push_back({P, p.velocity(P), state});
  }
  return ref;
}

}  // namespace granflow::test
