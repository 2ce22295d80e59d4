// Per-frame sums of the force-network model: coordination, deflections, fabric moments,
// angular and deflection histograms (network.hpp for the definitions).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "network/network.hpp"

namespace granflow::network {

Histograms::Histograms(std::size_t angle_bins, std::size_t deflection_bins)
    : angle_count(angle_bins, 0.0), angle_force(angle_bins, 0.0), angle_branch(angle_bins, 0.0),
      deflection_count(deflection_bins, 0.0) {
  if (angle_bins == 0 || deflection_bins == 0)
    throw std::invalid_argument("network histograms need at least one angle bin and one deflection bin");
}

void Histograms::add(const Histograms& other) {
  if (other.angle_count.size() != angle_count.size() || other.deflection_count.size() != deflection_count.size())
    throw std::invalid_argument("network histograms of different sizes cannot be added");
  for (std::size_t k = 0; k < angle_count.size(); ++k) {
    angle_count[k] += other.angle_count[k];
    angle_force[k] += other.angle_force[k];
    angle_branch[k] += other.angle_branch[k];
  }
  for (std::size_t k = 0; k < deflection_count.size(); ++k) deflection_count[k] += other.deflection_count[k];
}

namespace {

void check_columns(const ContactRecords& c) {
  const std::size_t n = c.pair.size();
  // Columns this analysis reads must match the pairs; the others may be absent (empty).
  bool ragged = c.branch.size() != n || c.binary_force.size() != n || c.age.size() != n;
  ragged = ragged || (!c.normal_force.empty() && c.normal_force.size() != n);
  ragged = ragged || (!c.tangential_force.empty() && c.tangential_force.size() != n);
  ragged = ragged || (!c.pre_normal_velocity.empty() && c.pre_normal_velocity.size() != n);
  if (ragged) throw std::invalid_argument("contact columns of different lengths (" + std::to_string(n) + " pairs)");
}

// Bin of a value in [0, range] split into `bins` equal bins; the upper end goes into the last.
std::size_t bin_of(double value, double range, std::size_t bins) {
  const double k = std::floor(value / range * double(bins));
  if (!(k > 0)) return 0;
  return std::min(std::size_t(k), bins - 1);
}

}  // namespace

FrameSums FrameAnalyser::analyse(const ContactRecords& contacts, std::size_t grains, Histograms* h) {
  check_columns(contacts);
  const std::size_t n = contacts.size();
  FrameSums s;
  s.grains = double(grains);
  s.contacts = double(n);

  // Pass 1: validate, moments over all contacts, histograms, degree of long-lived contacts.
  start_.assign(grains + 1, 0);
  for (std::size_t c = 0; c < n; ++c) {
    const auto [i, j] = contacts.pair[c];
    if (i < 0 || j < 0 || std::size_t(i) >= grains || std::size_t(j) >= grains)
      throw std::invalid_argument("contact " + std::to_string(c) + " names grain pair (" + std::to_string(i) + ", " +
                                  std::to_string(j) + ") outside 0.." + std::to_string(grains) + "-1");
    if (i == j)
      throw std::invalid_argument("contact " + std::to_string(c) + " pairs grain " + std::to_string(i) +
                                  " with itself");
    const Vec2& b = contacts.branch[c];
    const double length = b.norm();
    if (!(length > 0) || !std::isfinite(length))
      throw std::invalid_argument("contact " + std::to_string(c) + " has a zero or non-finite branch vector");
    const double nx = b.x() / length, ny = b.y() / length;
    const double sin2 = 2 * nx * ny, cos2 = nx * nx - ny * ny;
    const double f = contacts.binary_force[c];
    s.sum_sin2 += sin2;
    s.sum_cos2 += cos2;
    s.sum_f += f;
    s.sum_f_sin2 += f * sin2;
    s.sum_f_cos2 += f * cos2;
    s.sum_b += length;
    s.sum_b_sin2 += length * sin2;
    s.sum_b_cos2 += length * cos2;
    s.sum_bf += length * f;
    s.sum_bf_sin2 += length * f * sin2;
    s.sum_bf_cos2 += length * f * cos2;
    if (h) {
      // θ folded into [0, π): n̂ and −n̂ are the same contact direction.
      const bool flip = ny < 0 || (ny == 0 && nx < 0);
      const double theta = std::atan2(flip ? -ny : ny, flip ? -nx : nx);
      const std::size_t k = bin_of(theta, M_PI, h->angle_count.size());
      h->angle_count[k] += 1;
      h->angle_force[k] += f;
      h->angle_branch[k] += length;
    }
    if (contacts.age[c] >= 2) {
      ++start_[std::size_t(i) + 1];
      ++start_[std::size_t(j) + 1];
    }
  }

  // Pass 2: per-grain lists of long-lived partners (counting sort into CSR).
  for (std::size_t g = 0; g < grains; ++g) {
    if (start_[g + 1] > 0) s.active_grains += 1;
    start_[g + 1] += start_[g];
  }
  const std::size_t ends = start_[grains];
  s.long_lived = double(ends / 2);
  fill_.assign(start_.begin(), start_.end() - 1);
  ux_.resize(ends);
  uy_.resize(ends);
  for (std::size_t c = 0; c < n; ++c) {
    if (contacts.age[c] < 2) continue;
    const auto [i, j] = contacts.pair[c];
    const Vec2& b = contacts.branch[c];
    const double length = b.norm();
    const double nx = b.x() / length, ny = b.y() / length;
    // branch = r_i − r_j: from i the partner j lies along −n̂, from j the partner i along +n̂.
    const std::size_t at_i = fill_[std::size_t(i)]++, at_j = fill_[std::size_t(j)]++;
    ux_[at_i] = -nx;
    uy_[at_i] = -ny;
    ux_[at_j] = nx;
    uy_[at_j] = ny;
  }

  // Pass 3: every unordered pair of distinct long-lived partners of one grain.
  const std::size_t bins = h ? h->deflection_count.size() : 0;
  for (std::size_t g = 0; g < grains; ++g) {
    const std::size_t lo = start_[g], hi = start_[g + 1];
    for (std::size_t a = lo; a < hi; ++a) {
      for (std::size_t b = a + 1; b < hi; ++b) {
        // cos x = −u_{I→m}·u_{I→J}: a straight chain (partners on opposite sides) has x = 0.
        const double cx = std::clamp(-(ux_[a] * ux_[b] + uy_[a] * uy_[b]), -1.0, 1.0);
        s.deflection_pairs += 1;
        s.sum_cos += cx;
        s.sum_cos_cos2 += cx * (2 * cx * cx - 1);
        if (h) h->deflection_count[bin_of(std::acos(cx), M_PI, bins)] += 1;
      }
    }
  }
  return s;
}

}  // namespace granflow::network
