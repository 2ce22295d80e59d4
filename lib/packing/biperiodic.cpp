// Biperiodic packings by grow-and-relax (thesis App. A.3): the radii grow by a
// common factor in steps from a dilute random start; after each step the harmonic
// overlap energy E = ½ Σ δ² is minimised with FIRE 2.0 (Guénolé et al., Comput.
// Mater. Sci. 175, 109584 (2020)). Minimising instead of integrating damped
// dynamics reaches overlaps of 1e-9σ in a few thousand steps.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <sstream>

#include "core/cli.hpp"

#include "core/error.hpp"
#include "core/signals.hpp"
#include "neighbours/cell_list.hpp"
#include "packing/input_rules.hpp"
#include "packing/packing.hpp"

namespace granflow {
namespace {

// Growth schedule: a random start at this packing fraction has many overlaps but
// relaxes in a few hundred steps; the radii then grow by this much ν per stage,
// small enough that every stage only needs a short relaxation.
constexpr double start_fraction = 0.4;
constexpr double stage_fraction_step = 0.02;
// Intermediate stages are relaxed only to this max overlap (units of σ): the
// structure follows the growth, and only the last stage needs full precision.
constexpr double stage_tolerance = 1e-3;

// FIRE 2.0 parameters, unit mass and stiffness. The fastest contact modes have
// ω² ≲ 2z ≈ 12, so dt_max = 0.5 sits just below the stability limit; measured,
// dt_max ≥ 0.7 needs 7× more steps at ν = 0.82 and far more near jamming.
constexpr double dt_start = 0.1, dt_max = 0.5, dt_min = 0.002;
constexpr int n_delay = 20;
constexpr double f_inc = 1.1, f_dec = 0.5, alpha_start = 0.25, f_alpha = 0.99;
// "The energy stops decreasing": over a window of this many steps the lowest energy
// seen fell by less than stall_fraction (a jammed packing at its energy minimum), or
// over creep_windows windows it did not halve (a marginal packing creeping along
// nearly flat directions of the landscape, which may take millions of steps).
constexpr std::int64_t stall_window = 2000;
constexpr double stall_fraction = 1e-3;
constexpr std::size_t creep_windows = 20;
// Steps between progress reports (≈ 1 s at N = 10^5).
constexpr std::int64_t report_every = 250;

// Soft disks of radii scale·r_i in a fixed biperiodic box, with a Verlet list whose
// skin is rebuilt as soon as any grain moved more than skin/2 since the last build.
class SoftDisks {
 public:
  SoftDisks(const Box& box, std::vector<double> radius, std::vector<Vec2> position, double skin)
      : box_(box), radius_(std::move(radius)), x_(std::move(position)), skin_(skin) {
    r_max_ = *std::max_element(radius_.begin(), radius_.end());
    v_.assign(x_.size(), Vec2::Zero());
    f_.assign(x_.size(), Vec2::Zero());
    scaled_.resize(radius_.size());
  }

  void set_scale(double scale) {
    scale_ = scale;
    for (std::size_t i = 0; i < radius_.size(); ++i) scaled_[i] = scale * radius_[i];
    rebuild();
  }

  // Minimises E at the current scale until max overlap < tolerance (absolute) or the
  // energy stalls, calling report(max overlap) now and then. Returns the steps taken.
  std::int64_t relax(double tolerance, const std::function<void(double)>& report) {
    std::fill(v_.begin(), v_.end(), Vec2::Zero());
    compute_forces();
    double dt = dt_start, alpha = alpha_start;
    int n_positive = 0;
    double best = energy_;
    std::vector<double> best_at_window_start{best};
    std::int64_t step = 0;
    while (max_overlap_ >= tolerance) {
      check_interrupt();
      if (step % report_every == 0 && step > 0) report(max_overlap_);
      if (step % stall_window == 0 && step > 0) {
        const std::size_t w = best_at_window_start.size();
        if (best > (1 - stall_fraction) * best_at_window_start[w - 1]) break;
        if (w >= creep_windows && best > 0.5 * best_at_window_start[w - creep_windows]) break;
        best_at_window_start.push_back(best);
      }
      double power = 0, v2 = 0, f2 = 0;
      for (std::size_t i = 0; i < x_.size(); ++i) power += f_[i].dot(v_[i]);
      if (power > 0) {
        if (++n_positive > n_delay) {
          dt = std::min(dt * f_inc, dt_max);
          alpha *= f_alpha;
        }
      } else {
        // Overshoot: step back half a step, stop, and restart more cautiously.
        n_positive = 0;
        if (step >= n_delay) {
          dt = std::max(dt * f_dec, dt_min);
          alpha = alpha_start;
        }
        for (std::size_t i = 0; i < x_.size(); ++i) {
          x_[i] -= 0.5 * dt * v_[i];
          v_[i].setZero();
        }
      }
      for (std::size_t i = 0; i < x_.size(); ++i) {
        v_[i] += dt * f_[i];
        v2 += v_[i].squaredNorm();
        f2 += f_[i].squaredNorm();
      }
      // Steer the velocity towards the force: v ← (1−α)v + α|v| F̂.
      const double mix = f2 > 0 ? alpha * std::sqrt(v2 / f2) : 0;
      double moved2 = 0;
      for (std::size_t i = 0; i < x_.size(); ++i) {
        v_[i] = (1 - alpha) * v_[i] + mix * f_[i];
        x_[i] += dt * v_[i];
        moved2 = std::max(moved2, (x_[i] - x_built_[i]).squaredNorm());
      }
      if (4 * moved2 > skin_ * skin_) rebuild();
      compute_forces();
      best = std::min(best, energy_);
      ++step;
    }
    return step;
  }

  double max_overlap() const { return max_overlap_; }
  const std::vector<Vec2>& positions() const { return x_; }

 private:
  struct Pair {
    int i, j;
    Vec2 shift;  // periodic image: the separation is x_i − x_j + shift
  };

  void rebuild() {
    for (Vec2& r : x_) {
      Vec2 unused_velocity = Vec2::Zero();
      box_.wrap(r, unused_velocity, 0);
    }
    x_built_ = x_;
    pairs_.clear();
    CellList cells;
    cells.build(x_, box_, 2 * scale_ * r_max_ + skin_);
    cells.for_each_pair(x_, [&](int i, int j, const Vec2& d) {
      const double reach = scaled_[i] + scaled_[j] + skin_;
      if (d.squaredNorm() < reach * reach) pairs_.push_back({i, j, d - (x_[i] - x_[j])});
    });
  }

  void compute_forces() {
    std::fill(f_.begin(), f_.end(), Vec2::Zero());
    energy_ = 0;
    max_overlap_ = 0;
    for (const Pair& p : pairs_) {
      const Vec2 d = x_[p.i] - x_[p.j] + p.shift;
      const double contact = scaled_[p.i] + scaled_[p.j];
      const double r2 = d.squaredNorm();
      if (r2 >= contact * contact) continue;
      const double r = std::sqrt(r2);
      const double overlap = contact - r;
      const Vec2 f = (overlap / r) * d;
      f_[p.i] += f;
      f_[p.j] -= f;
      energy_ += 0.5 * overlap * overlap;
      max_overlap_ = std::max(max_overlap_, overlap);
    }
  }

  Box box_;
  std::vector<double> radius_, scaled_;
  std::vector<Vec2> x_, v_, f_, x_built_;
  std::vector<Pair> pairs_;
  double skin_, r_max_ = 0, scale_ = 1;
  double energy_ = 0, max_overlap_ = 0;
};

// Grows the radii of disks (already in a box sized for the target) in stages from
// packing fraction nu0 to nu, relaxing after each; the last stage down to tolerance.
std::int64_t grow_and_relax(SoftDisks& disks, double nu0, double nu, double sigma, double overlap_tolerance,
                            const std::function<void(double fraction_done, double max_overlap)>& progress) {
  const int stages = std::max(0, int(std::ceil((nu - nu0) / stage_fraction_step)));
  const double tolerance = overlap_tolerance * sigma;
  const double log_sigma = std::log(sigma);
  std::int64_t iterations = 0;
  for (int k = 0; k <= stages; ++k) {
    const bool last = k == stages;
    const double nu_k = last ? nu : nu0 + (nu - nu0) * k / stages;
    disks.set_scale(last ? 1.0 : std::sqrt(nu_k / nu));
    // Progress: growth is the first half; the final relaxation the second, measured
    // by how far log(max overlap) has come down from log σ towards log(tolerance).
    const double growth_done = last ? 0.5 : 0.5 * k / stages;
    auto report = [&](double overlap) {
      if (!progress) return;
      double done = growth_done;
      if (last)
        done += overlap < tolerance
                    ? 0.5
                    : 0.5 * std::clamp((log_sigma - std::log(overlap)) / (log_sigma - std::log(tolerance)), 0.0, 1.0);
      progress(done, overlap / sigma);
    };
    iterations += disks.relax(last ? tolerance : stage_tolerance * sigma, report);
    report(disks.max_overlap());
  }
  return iterations;
}

// A pair may interact through one periodic image only (minimum image, one image per
// Verlet-list entry): the box must exceed twice the largest reach.
void require_box_fits(const Box& box, const std::vector<double>& radius, double skin, std::int64_t grains,
                      double packing_fraction) {
  const double reach = 2 * *std::max_element(radius.begin(), radius.end()) + skin;
  const double side = std::min(box.lx, box.ly);
  if (side <= 2 * reach) {
    std::ostringstream msg;
    msg << "--grains: " << grains << " grains at packing fraction " << packing_fraction << " give a box of side "
        << side << ", not larger than twice the largest diameter plus the neighbour skin (" << 2 * reach
        << "); use more grains";
    throw UsageError(msg.str());
  }
}

void finish(Packing& out, const SoftDisks& disks, double area, std::chrono::steady_clock::time_point t0) {
  out.position = disks.positions();
  for (Vec2& r : out.position) {
    Vec2 unused_velocity = Vec2::Zero();
    out.box.wrap(r, unused_velocity, 0);
  }
  out.fixed.assign(out.radius.size(), 0);
  out.packing_fraction = area / out.box.area();
  out.max_overlap = max_overlap(out.box, out.position, out.radius);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double disk_area(const std::vector<double>& radius) {
  double area = 0;
  for (double r : radius) area += M_PI * r * r;
  return area;
}

}  // namespace

Packing make_biperiodic_packing(const PackingParams& p,
                                const std::function<void(double fraction_done, double max_overlap)>& progress) {
  validate(p);
  const auto t0 = std::chrono::steady_clock::now();
  const double sigma = p.mean_diameter;
  Rng rng(p.seed);

  Packing out;
  out.radius = draw_radii(p.grains, sigma, p.polydispersity, rng);
  const double area = disk_area(out.radius);
  const double side = std::sqrt(area / p.packing_fraction);
  out.box = Box{side, side, true, 0.0};
  const double skin = 0.2 * sigma;
  require_box_fits(out.box, out.radius, skin, p.grains, p.packing_fraction);

  std::vector<Vec2> start(out.radius.size());
  for (Vec2& r : start) {
    const double x = rng.uniform(0, side);
    r = Vec2(x, rng.uniform(0, side));
  }
  // Grains numbered band by band; the radii are drawn independently, so nothing is biased.
  std::sort(start.begin(), start.end(), [&](const Vec2& a, const Vec2& b) { return numbered_before(a, b, sigma); });
  SoftDisks disks(out.box, out.radius, std::move(start), skin);
  out.iterations = grow_and_relax(disks, std::min(start_fraction, p.packing_fraction), p.packing_fraction, sigma,
                                  p.overlap_tolerance, progress);
  finish(out, disks, area, t0);
  return out;
}

Packing repack(const Packing& start, double packing_fraction, double overlap_tolerance,
               const std::function<void(double fraction_done, double max_overlap)>& progress) {
  require_in_range("packing-fraction", packing_fraction, 0.0, 0.91, true, true);
  require_positive("tolerance", overlap_tolerance);
  require_biperiodic_input(start, "repacked");
  const auto t0 = std::chrono::steady_clock::now();
  const double area = disk_area(start.radius);
  const double sigma = 2 * std::accumulate(start.radius.begin(), start.radius.end(), 0.0) / double(start.radius.size());
  const double old_fraction = area / start.box.area();
  // Same shape, scaled so that ν is exact; the Lees–Edwards offset of a sheared frame
  // is dropped (the relaxation removes what that changes at the top boundary).
  const double scale = std::sqrt(old_fraction / packing_fraction);
  Packing out;
  out.radius = start.radius;
  out.box = Box{start.box.lx * scale, start.box.ly * scale, true, 0.0};
  const double skin = 0.2 * sigma;
  require_box_fits(out.box, out.radius, skin, std::int64_t(out.radius.size()), packing_fraction);
  std::vector<Vec2> position(start.position.size());
  for (std::size_t i = 0; i < position.size(); ++i) position[i] = start.position[i] * scale;
  SoftDisks disks(out.box, out.radius, std::move(position), skin);
  out.iterations = grow_and_relax(disks, std::min(old_fraction, packing_fraction), packing_fraction, sigma,
                                  overlap_tolerance, progress);
  finish(out, disks, area, t0);
  return out;
}

}  // namespace granflow
