#include "dynamics/region_solver.hpp"

#include <algorithm>
#include <cmath>

#include "dynamics/capacity.hpp"
#include "dynamics/contact_law.hpp"
#include "dynamics/lemke.hpp"
#include "dynamics/parallel.hpp"

namespace granflow {

namespace {

// Pivots allowed per unknown of the region's problem: Lemke's method takes about one per
// unknown that ends nonzero; far more means cycling on round-off.
constexpr int kPivotsPerUnknown = 10;

}  // namespace

void RegionSolver::gather_region(const ContactRows& contacts, const std::vector<int>& work, double mu,
                                 double upsilon, double fraction, int depth) {
  const int n = int(contacts.bodies().size());
  const auto& row_bodies = contacts.row_bodies();
  counting_sort(
      std::size_t(n), body_start_,
      [&](auto emit) {
        for (int c : work)
          for (int b : row_bodies[c])
            if (b >= 0) emit(std::size_t(b), c);
      },
      [&](std::size_t total) { refill(body_rows_, total); }, [&](int c, int slot) { body_rows_[slot] = c; });
  in_region_body_.assign(std::size_t(n), 0);
  bodies_.clear();
  auto add_bodies = [&](int c) {
    for (int b : row_bodies[c])
      if (b >= 0 && !in_region_body_[b]) {
        in_region_body_[b] = 1;
        bodies_.push_back(b);
      }
  };
  // The seeds: the rows a local solve would still correct by at least `fraction` of the
  // largest such correction (and by Υ).
  const auto& rows = contacts.rows();
  const auto& tangents = contacts.tangents();
  const auto& bodies = contacts.bodies();
  correction_.resize(work.size());
  double largest = 0;
  for (std::size_t q = 0; q < work.size(); ++q) {
    const int c = work[q];
    const Row& r = rows[c];
    const Local l = local_solve(r, tangents[c], bodies[r.i], bodies[r.j], mu);
    correction_[q] = correction(r, tangents[c], l);
    largest = std::max(largest, correction_[q]);
  }
  const double seed = std::max(upsilon, fraction * largest);
  for (std::size_t q = 0; q < work.size(); ++q)
    if (correction_[q] >= seed) add_bodies(work[q]);
  // Each round adds the grains of the rows touching the region's grains so far.
  for (int round = 0; round < depth; ++round) {
    const std::size_t reached = bodies_.size();
    for (std::size_t k = 0; k < reached; ++k)
      for (int s = body_start_[bodies_[k]]; s < body_start_[bodies_[k] + 1]; ++s) add_bodies(body_rows_[s]);
  }
  region_.clear();
  mark_.resize(contacts.size());
  for (int b : bodies_)
    for (int s = body_start_[b]; s < body_start_[b + 1]; ++s) region_.push_back(body_rows_[s]);
  std::sort(region_.begin(), region_.end());
  region_.erase(std::unique(region_.begin(), region_.end()), region_.end());
}

// W = the region rows' Delassus matrix (u_n, u_t of each row against P_n, P_t of each,
// interleaved), from the grains they share: a unit impulse of row l moves its grain g by
// σ_l·(n̂_l or t̂_l)/m and changes its spin s = Rω by −2/m per unit P_t; row k reads
// σ_k·Δv·n̂_k and σ_k·Δv·t̂_k − Δs (σ = +1 on a row's first grain, −1 on its second).
RegionSolver::Problem RegionSolver::assemble(const ContactRows& contacts, double mu) const {
  const int m = int(region_.size());
  const auto& rows = contacts.rows();
  const auto& tangents = contacts.tangents();
  const auto& bodies = contacts.bodies();
  const auto& row_bodies = contacts.row_bodies();
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(2 * m, 2 * m);
  // Every mobile grain of a region row couples the region rows touching it.
  std::vector<int> local;
  for (int k = 0; k < m; ++k)
    for (int g : row_bodies[region_[k]]) {
      if (g < 0) continue;
      local.clear();
      for (int s = body_start_[g]; s < body_start_[g + 1]; ++s)
        if (mark_[body_rows_[s]]) local.push_back(body_rows_[s]);
      const double w = bodies[g].inv_mass;
      const Row& rk = rows[region_[k]];
      const double sk = rk.i == g ? 1.0 : -1.0;
      const double tkx = -rk.ny, tky = rk.nx;
      for (int c : local) {
        const int l = mark_[c] - 1;
        const Row& rl = rows[c];
        const double sl = rl.i == g ? 1.0 : -1.0;
        const double tlx = -rl.ny, tly = rl.nx;
        const double f = sk * sl * w;
        W(2 * k, 2 * l) += f * (rk.nx * rl.nx + rk.ny * rl.ny);
        W(2 * k, 2 * l + 1) += f * (rk.nx * tlx + rk.ny * tly);
        W(2 * k + 1, 2 * l) += f * (tkx * rl.nx + tky * rl.ny);
        W(2 * k + 1, 2 * l + 1) += f * (tkx * tlx + tky * tly) + 2 * w;
      }
    }
  // Impulses as velocities: P·scale_, scale_ the mean W_nn, so that every entry of the
  // problem is of one order.
  double sum = 0;
  for (int k = 0; k < m; ++k) sum += 1 / rows[region_[k]].inv_w;
  Problem p;
  p.scale = sum / m;
  W /= p.scale;
  Eigen::VectorXd p_now(2 * m);
  for (int k = 0; k < m; ++k) {
    p_now(2 * k) = rows[region_[k]].pn * p.scale;
    p_now(2 * k + 1) = tangents[region_[k]].pt * p.scale;
  }
  // The rows' distance from their bounds at P = 0, the others held: u_now − b − W·P_now.
  Eigen::VectorXd r = -(W * p_now);
  for (int k = 0; k < m; ++k) {
    const Row& row = rows[region_[k]];
    const Body& a = bodies[row.i];
    const Body& b = bodies[row.j];
    const double dvx = a.vx - b.vx, dvy = a.vy - b.vy;
    r(2 * k) += dvx * row.nx + dvy * row.ny - row.bn;
    r(2 * k + 1) += dvy * row.nx - dvx * row.ny - (a.spin + b.spin) - tangents[region_[k]].bt;
  }
  const int n = 4 * m;
  p.M.setZero(n, n);
  p.q.setZero(n);
  for (int k = 0; k < m; ++k) {
    for (int l = 0; l < m; ++l) {
      const double nn = W(2 * k, 2 * l), nt = W(2 * k, 2 * l + 1);
      const double tn = W(2 * k + 1, 2 * l), tt = W(2 * k + 1, 2 * l + 1);
      p.M(4 * k, 4 * l) = nn;
      p.M(4 * k, 4 * l + 1) = nt;
      p.M(4 * k, 4 * l + 2) = -nt;
      p.M(4 * k + 1, 4 * l) = tn;
      p.M(4 * k + 1, 4 * l + 1) = tt;
      p.M(4 * k + 1, 4 * l + 2) = -tt;
      p.M(4 * k + 2, 4 * l) = -tn;
      p.M(4 * k + 2, 4 * l + 1) = -tt;
      p.M(4 * k + 2, 4 * l + 2) = tt;
    }
    p.M(4 * k + 1, 4 * k + 3) = 1;
    p.M(4 * k + 2, 4 * k + 3) = 1;
    p.M(4 * k + 3, 4 * k) = mu;
    p.M(4 * k + 3, 4 * k + 1) = -1;
    p.M(4 * k + 3, 4 * k + 2) = -1;
    p.q(4 * k) = r(2 * k);
    p.q(4 * k + 1) = r(2 * k + 1);
    p.q(4 * k + 2) = -r(2 * k + 1);
  }
  return p;
}

RegionSolver::Outcome RegionSolver::solve(ContactRows& contacts, const Tiling& tiling, const std::vector<int>& work,
                                          std::uint8_t* row_flags, std::uint8_t* moved, std::uint8_t* touched,
                                          double mu, double upsilon, double fraction, int depth, int max_rows) {
  Outcome out;
  gather_region(contacts, work, mu, upsilon, fraction, depth);
  out.rows = int(region_.size());
  if (region_.empty() || out.rows > max_rows) return out;
  const int m = out.rows;
  for (int k = 0; k < m; ++k) mark_[region_[k]] = k + 1;
  Eigen::VectorXd z;
  {
    const Problem p = assemble(contacts, mu);
    Lemke lemke;
    out.solved = lemke.solve(p.M, p.q, z, kPivotsPerUnknown * 4 * m);
    out.pivots = lemke.pivots();
    z /= p.scale;
  }
  auto& rows = contacts.rows();
  auto& tangents = contacts.tangents();
  auto& bodies = contacts.bodies();
  if (out.solved) {
    for (int k = 0; k < m; ++k) {
      const int c = region_[k];
      Row& r = rows[c];
      Tangent& t = tangents[c];
      const double pn = z(4 * k);
      // On a facet up to round-off: exactly on it, as a local solve would clamp it.
      const double pt = std::clamp(z(4 * k + 1) - z(4 * k + 2), -mu * pn, mu * pn);
      add_impulse(r, bodies[r.i], bodies[r.j], pn - r.pn, pt - t.pt);
      r.pn = pn;
      t.pt = pt;
      row_flags[c] = std::uint8_t(kHot | (pn > 0) * kBearing);
    }
    int tile = 0;
    for (int c : region_) {
      while (tiling.first_row(tile + 1) <= c) ++tile;
      moved[tile] = touched[tile] = 1;
    }
  }
  for (int c : region_) mark_[c] = 0;
  return out;
}

std::size_t RegionSolver::bytes() const {
  return heap_bytes(body_start_) + heap_bytes(body_rows_) + heap_bytes(region_) + heap_bytes(mark_) +
         heap_bytes(bodies_) + heap_bytes(in_region_body_) + heap_bytes(correction_);
}

}  // namespace granflow
