#pragma once
// The local contact laws of the engine (see engine.hpp), defined once: the Gauss–Seidel
// sweep applies them and the residual check measures how far the impulses are from them,
// so both always mean the same law, to the last bit. Row holds n̂, the bound b_n, 1/W_nn
// and P_n; Tangent the bound b_t and P_t; Body the velocity (vx, vy) and spin s = R·ω of a
// grain. Templates so that any layout with those members will do.
#include <algorithm>
#include <cmath>

#include "dynamics/branch_free.hpp"

namespace granflow {

// Which candidates the normal law constrains (see engine.hpp):
//  - predicted_gap: Moreau's activation, every candidate; one that touches or would touch
//    within the step is a contact, any other may close its gap but never go below zero;
//  - overlap: the thesis' (App. A.1): only pairs that touch or overlap at the start of the
//    step (g ≤ 0, found after the previous position update) are contacts; the others are
//    free, so a pair overlaps by up to dt·|u_n| before it first bounces, and an overlap is
//    never removed, only kept from growing.
enum class Activation { predicted_gap, overlap };

// New normal impulse of a local solve: P_n ← max(0, P_n + (b_n − u_n)/W_nn).
template <class Row, class Body>
inline double normal_impulse(const Row& r, const Body& a, const Body& b) {
  const double un = (a.vx - b.vx) * r.nx + (a.vy - b.vy) * r.ny;
  return positive_part(r.pn + (r.bn - un) * r.inv_w);
}

// Normal correction a local solve would make without friction (P_t = 0 throughout): the
// number correction(r, local_solve(r, a, b, 0)) gives, without its clamp and jumps.
template <class Row, class Body>
inline double normal_correction(const Row& r, const Body& a, const Body& b) {
  return std::fabs(normal_impulse(r, a, b) - r.pn) / r.inv_w;
}

// Exact solution of one contact's local problem given the other impulses: the normal
// impulse does not change u_t (W_nt = 0 for disks), so normal then tangential is exact.
struct Local {
  double pn, pt;
};

template <class Row, class Tangent, class Body>
inline Local local_solve(const Row& r, const Tangent& t, const Body& a, const Body& b, double mu) {
  const double dvx = a.vx - b.vx, dvy = a.vy - b.vy;
  const double ut = dvy * r.nx - dvx * r.ny - (a.spin + b.spin);
  const double pn = normal_impulse(r, a, b);
  const double limit = mu * pn;
  const double pt = std::clamp(t.pt + (t.bt - ut) * (r.inv_w * (1.0 / 3.0)), -limit, limit);
  return {pn, pt};
}

// Velocity correction made by a local solve: |ΔP_n|·W_nn and |ΔP_t|·W_tt.
template <class Row, class Tangent>
inline double correction(const Row& r, const Tangent& t, const Local& l) {
  return std::max(std::fabs(l.pn - r.pn), 3 * std::fabs(l.pt - t.pt)) / r.inv_w;
}

// Adds the impulse ΔP = ΔP_n n̂ + ΔP_t t̂ of row r to its grains' velocities: +ΔP on i, −ΔP on
// j, and ΔS = −2·ΔP_t/m on both (the torque of ±ΔP at the contact point, I = mR²/2).
template <class Row, class Body>
inline void add_impulse(const Row& r, Body& a, Body& b, double dpn, double dpt) {
  const double px = dpn * r.nx - dpt * r.ny, py = dpn * r.ny + dpt * r.nx;
  a.vx += a.inv_mass * px;
  a.vy += a.inv_mass * py;
  a.spin -= 2 * a.inv_mass * dpt;
  b.vx -= b.inv_mass * px;
  b.vy -= b.inv_mass * py;
  b.spin -= 2 * b.inv_mass * dpt;
}

}  // namespace granflow
