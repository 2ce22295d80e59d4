#include "incline/profiles.hpp"

#include <algorithm>
#include <cmath>

namespace granflow {

namespace {

// Area of the disk of radius r centred at 0 below the height h.
double area_below(double h, double r) {
  const double u = std::clamp(h / r, -1.0, 1.0);
  return r * r * (u * std::sqrt(1 - u * u) + std::asin(u) + 0.5 * M_PI);
}

constexpr ProfileColumnInfo kColumns[kProfileColumns] = {
    {"grains", "mobile grains with their centre in the layer", "1"},
    {"mass", "their mass Σm", "mass"},
    {"momentum_x", "Σ m v_x", "mass·velocity"},
    {"momentum_y", "Σ m v_y", "mass·velocity"},
    {"fluctuation_xx", "Σ (v_x − v̄_x)², v̄ the plain mean velocity of the layer's grains in the sample", "velocity²"},
    {"fluctuation_yy", "Σ (v_y − v̄_y)²", "velocity²"},
    {"fluctuation_xh", "Σ (v_x − v̄_x)(y − ȳ), ȳ their plain mean height", "velocity·length"},
    {"fluctuation_hh", "Σ (y − ȳ)²", "length²"},
    {"fluctuation_spin", "Σ R²(ω − ω̄)², ω̄ their plain mean angular velocity", "velocity²"},
    {"kinetic_xx", "Σ m (v_x − V_x)², V the mass-weighted mean velocity of the layer's grains in the sample",
     "mass·velocity²"},
    {"kinetic_xy", "Σ m (v_x − V_x)(v_y − V_y)", "mass·velocity²"},
    {"kinetic_yy", "Σ m (v_y − V_y)²", "mass·velocity²"},
    {"kinetic_xh", "Σ m (v_x − V_x)(y − Y), Y their mass-weighted mean height", "mass·velocity·length"},
    {"kinetic_yh", "Σ m (v_y − V_y)(y − Y)", "mass·velocity·length"},
    {"kinetic_hh", "Σ m (y − Y)²", "mass·length²"},
    {"contact_xx",
     "Σ over contacts of F_x b_x × the fraction of the branch segment r_j→r_i inside the layer "
     "(b = r_i − r_j, F the force on i)",
     "force·length"},
    {"contact_xy", "Σ over contacts of F_x b_y × the fraction of the branch segment inside the layer", "force·length"},
    {"contact_yx", "Σ over contacts of F_y b_x × the fraction of the branch segment inside the layer", "force·length"},
    {"contact_yy", "Σ over contacts of F_y b_y × the fraction of the branch segment inside the layer", "force·length"},
    {"area", "area of all disks (base grains included) inside the layer", "length²"},
    {"mass_above", "average over heights y in the layer of the mass of the mobile grains with centre above y", "mass"},
};

}  // namespace

double disk_strip_area(double yc, double r, double a, double b) {
  return area_below(b - yc, r) - area_below(a - yc, r);
}

ProfileGrid profile_grid(const Box& box, double bin) {
  ProfileGrid grid;
  grid.bin = bin;
  grid.bins = std::max(1, int(std::ceil(box.ly / bin)));
  grid.lx = box.lx;
  return grid;
}

const ProfileColumnInfo& profile_column(int column) { return kColumns[column]; }

std::int64_t automatic_profile_block(std::int64_t steps) { return std::clamp<std::int64_t>(steps / 20, 1, 5000); }

InclineObservables incline_observables(const GrainState& s) {
  InclineObservables o;
  double mass = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.fixed[i]) continue;
    const double m = s.mass[i], r = s.radius[i], w = s.angular_velocity[i];
    mass += m;
    o.flow_rate += m * s.velocity[i].x();
    o.height += m * s.position[i].y();
    o.kinetic_energy += 0.5 * m * s.velocity[i].squaredNorm() + 0.25 * m * r * r * w * w;
  }
  if (mass > 0) {
    o.flow_rate /= mass;
    o.height /= mass;
  }
  return o;
}

ProfileAccumulator::ProfileAccumulator(ProfileGrid grid, std::int64_t block_steps)
    : grid_(grid), block_steps_(block_steps) {
  const std::size_t n = std::size_t(grid_.bins);
  count_.resize(n);
  mass_.resize(n);
  height_.resize(n);
  mass_height_.resize(n);
  spin_.resize(n);
  velocity_.resize(n);
  momentum_.resize(n);
}

void ProfileAccumulator::add(std::int64_t step, double time, const GrainState& s, const ContactRecords& contacts,
                             const InclineObservables& o) {
  const int bins = grid_.bins;
  const double dy = grid_.bin;
  const std::int64_t index = (step - 1) / block_steps_;
  if (blocks_.empty() || blocks_.back().index != index) {
    ProfileBlock block;
    block.index = index;
    block.time_begin = time;
    block.sums.assign(std::size_t(kProfileColumns) * std::size_t(bins), 0.0);
    blocks_.push_back(std::move(block));
  }
  ProfileBlock& block = blocks_.back();
  ++block.samples;
  block.time_end = time;
  block.observables.flow_rate += o.flow_rate;
  block.observables.kinetic_energy += o.kinetic_energy;
  block.observables.height += o.height;
  auto sum = [&](int column, int k) -> double& { return block.sums[std::size_t(column * bins + k)]; };
  auto layer_of = [&](double y) { return std::clamp(int(std::floor(y / dy)), 0, bins - 1); };

  // Layer means of this sample (first pass), then the sums about them (second pass):
  // two passes keep the fluctuations exact next to a large mean flow.
  std::fill(count_.begin(), count_.end(), 0.0);
  std::fill(mass_.begin(), mass_.end(), 0.0);
  std::fill(height_.begin(), height_.end(), 0.0);
  std::fill(mass_height_.begin(), mass_height_.end(), 0.0);
  std::fill(spin_.begin(), spin_.end(), 0.0);
  std::fill(velocity_.begin(), velocity_.end(), Vec2::Zero());
  std::fill(momentum_.begin(), momentum_.end(), Vec2::Zero());
  layer_.assign(s.size(), -1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double r = s.radius[i], y = s.position[i].y();
    // Area: every disk, over the layers it overlaps.
    const int lo = std::max(0, int(std::floor((y - r) / dy))), hi = std::min(bins - 1, int(std::floor((y + r) / dy)));
    for (int k = lo; k <= hi; ++k) sum(kArea, k) += disk_strip_area(y, r, k * dy, (k + 1) * dy);
    if (s.fixed[i]) continue;
    const int k = layer_of(y);
    layer_[i] = k;
    const double m = s.mass[i];
    count_[k] += 1;
    mass_[k] += m;
    height_[k] += y;
    mass_height_[k] += m * y;
    spin_[k] += s.angular_velocity[i];
    velocity_[k] += s.velocity[i];
    momentum_[k] += m * s.velocity[i];
    // Mass above heights inside its own layer: the fraction of the layer below it.
    sum(kMassAbove, k) += m * (y - k * dy) / dy;
  }
  double above = 0;  // mass of the layers above k
  for (int k = bins - 1; k >= 0; --k) {
    sum(kMassAbove, k) += above;
    above += mass_[k];
    sum(kGrains, k) += count_[k];
    sum(kMass, k) += mass_[k];
    sum(kMomentumX, k) += momentum_[k].x();
    sum(kMomentumY, k) += momentum_[k].y();
    if (count_[k] == 0) continue;
    velocity_[k] /= count_[k];
    height_[k] /= count_[k];
    spin_[k] /= count_[k];
    momentum_[k] /= mass_[k];
    mass_height_[k] /= mass_[k];
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    const int k = layer_[i];
    if (k < 0) continue;
    const double m = s.mass[i], y = s.position[i].y();
    const Vec2 dv = s.velocity[i] - velocity_[k];
    const double dh = y - height_[k];
    const double dw = s.radius[i] * (s.angular_velocity[i] - spin_[k]);
    sum(kFluctuationXX, k) += dv.x() * dv.x();
    sum(kFluctuationYY, k) += dv.y() * dv.y();
    sum(kFluctuationXH, k) += dv.x() * dh;
    sum(kFluctuationHH, k) += dh * dh;
    sum(kFluctuationSpin, k) += dw * dw;
    const Vec2 du = s.velocity[i] - momentum_[k];
    const double dz = y - mass_height_[k];
    sum(kKineticXX, k) += m * du.x() * du.x();
    sum(kKineticXY, k) += m * du.x() * du.y();
    sum(kKineticYY, k) += m * du.y() * du.y();
    sum(kKineticXH, k) += m * du.x() * dz;
    sum(kKineticYH, k) += m * du.y() * dz;
    sum(kKineticHH, k) += m * dz * dz;
  }

  // Contacts: the branch segment from y_j to y_i, split among the layers it crosses. The
  // force acts along the recorded branch (the step's geometry); the segment joins the
  // centres after the step, where the weight is counted too, so that a contact carries
  // momentum through exactly the lines that separate its grains after the step (the
  // balance of the discrete dynamics).
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const Vec2& branch = contacts.branch[c];
    const Vec2 n = branch / branch.norm();
    const Vec2 f = contacts.normal_force[c] * n + contacts.tangential_force[c] * perp(n);
    const double yi = s.position[std::size_t(contacts.pair[c][0])].y();
    const double yj = s.position[std::size_t(contacts.pair[c][1])].y();
    const Vec2 b(branch.x(), yi - yj);
    const double lo = std::min(yi, yj), hi = std::max(yi, yj);
    auto deposit = [&](int k, double fraction) {
      sum(kContactXX, k) += fraction * f.x() * b.x();
      sum(kContactXY, k) += fraction * f.x() * b.y();
      sum(kContactYX, k) += fraction * f.y() * b.x();
      sum(kContactYY, k) += fraction * f.y() * b.y();
    };
    if (hi == lo) {
      deposit(layer_of(yi), 1.0);
      continue;
    }
    const int k0 = layer_of(lo), k1 = layer_of(hi);
    for (int k = k0; k <= k1; ++k) {
      const double inside = std::min(hi, (k + 1) * dy) - std::max(lo, k * dy);
      if (inside > 0) deposit(k, inside / (hi - lo));
    }
  }
}

Profiles average_profiles(const ProfileGrid& grid, const std::vector<ProfileBlock>& blocks, std::size_t first, double g,
                          double mean_radius, double mean_mass) {
  const int bins = grid.bins;
  std::vector<double> total(std::size_t(kProfileColumns) * std::size_t(bins), 0.0);
  Profiles p;
  for (std::size_t b = first; b < blocks.size(); ++b) {
    p.samples += blocks[b].samples;
    for (std::size_t k = 0; k < total.size(); ++k) total[k] += blocks[b].sums[k];
  }
  auto at = [&](int column, int k) { return total[std::size_t(column * bins + k)]; };
  int used = 0;
  for (int k = 0; k < bins; ++k)
    if (at(kMass, k) > 0) used = k + 1;

  const double nan = std::nan("");
  const double samples = double(p.samples);
  const double area = grid.layer_area() * samples;  // layer area × samples: turns sums into densities
  auto resize = [&](std::vector<double>& v) { v.assign(std::size_t(used), nan); };
  for (auto* v :
       {&p.y, &p.packing_fraction, &p.velocity_x, &p.shear_rate, &p.temperature, &p.stress_xx, &p.stress_xy,
        &p.stress_yy, &p.pressure, &p.shear_stress, &p.weight_above, &p.s_over_p, &p.inertial, &p.mT_over_pR2})
    resize(*v);
  for (int k = 0; k < used; ++k) {
    p.y[k] = (k + 0.5) * grid.bin;
    p.packing_fraction[k] = at(kArea, k) / area;
    p.weight_above[k] = g * at(kMassAbove, k) / (grid.lx * samples);
    if (at(kMass, k) > 0) p.velocity_x[k] = at(kMomentumX, k) / at(kMass, k);
  }
  // Central differences between the nearest layers below and above that hold grains.
  std::vector<int> held;
  for (int k = 0; k < used; ++k)
    if (at(kMass, k) > 0) held.push_back(k);
  for (std::size_t h = 0; h < held.size(); ++h) {
    const int lo = held[h > 0 ? h - 1 : h], hi = held[std::min(h + 1, held.size() - 1)];
    if (hi > lo) p.shear_rate[held[h]] = (p.velocity_x[hi] - p.velocity_x[lo]) / ((hi - lo) * grid.bin);
  }
  for (int k = 0; k < used; ++k) {
    const double shear = p.shear_rate[k];
    // Layers without grain centres carry contact stress only (and no shear to remove).
    const bool grains = at(kGrains, k) > 0;
    if (grains)
      p.temperature[k] =
          (at(kFluctuationXX, k) - 2 * shear * at(kFluctuationXH, k) + shear * shear * at(kFluctuationHH, k) +
           at(kFluctuationYY, k) + 0.5 * at(kFluctuationSpin, k)) /
          at(kGrains, k);
    const double kxx =
        grains ? at(kKineticXX, k) - 2 * shear * at(kKineticXH, k) + shear * shear * at(kKineticHH, k) : 0.0;
    const double kxy = grains ? at(kKineticXY, k) - shear * at(kKineticYH, k) : 0.0;
    p.stress_xx[k] = (kxx + at(kContactXX, k)) / area;
    p.stress_xy[k] = (kxy + at(kContactXY, k)) / area;
    p.stress_yy[k] = (at(kKineticYY, k) + at(kContactYY, k)) / area;
    p.pressure[k] = 0.5 * (p.stress_xx[k] + p.stress_yy[k]);
    p.shear_stress[k] = -p.stress_xy[k];
    p.s_over_p[k] = p.shear_stress[k] / p.pressure[k];
    p.inertial[k] = shear * mean_radius / std::sqrt(p.temperature[k]);
    p.mT_over_pR2[k] = mean_mass * p.temperature[k] / (p.pressure[k] * mean_radius * mean_radius);
  }
  return p;
}

}  // namespace granflow
