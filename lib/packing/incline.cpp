// Incline start (thesis App. A.3): grains "start in a very dilute packing and are
// allowed to collapse under gravity onto a plane consisting of grains that are
// fixed". The collapse is gf-incline's job; here we only lay out the grains.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "packing/packing.hpp"

namespace granflow {

Packing make_incline_packing(const InclineParams& p) {
  validate(p);
  const auto t0 = std::chrono::steady_clock::now();
  const double sigma = p.mean_diameter;
  const double d_max = sigma * (1 + p.polydispersity);
  Rng rng(p.seed);
  Packing out;

  // Base: touching grains along y = 0; lx is their total diameter, so the last one
  // touches the first through the periodic boundary.
  double lx = 0;
  while (lx < p.width * sigma) {
    const double r = draw_radii(1, sigma, p.polydispersity, rng)[0];
    out.position.emplace_back(lx + r, 0.0);
    out.radius.push_back(r);
    lx += 2 * r;
  }
  const std::size_t base = out.radius.size();
  const double base_top = *std::max_element(out.radius.begin(), out.radius.end());

  // Mobile grains: a layer of thickness height·σ at ν ≈ 0.8 holds 0.8·lx·h / (π⟨r²⟩)
  // grains, with ⟨r²⟩ = σ²(1 + (Δ/σ)²/3)/4 for uniform diameters.
  const double mean_r2 = 0.25 * sigma * sigma * (1 + p.polydispersity * p.polydispersity / 3);
  const std::int64_t mobile =
      p.grains > 0 ? p.grains : std::max<std::int64_t>(1, std::llround(0.8 * lx * p.height * sigma / (M_PI * mean_r2)));
  const std::vector<double> radius = draw_radii(mobile, sigma, p.polydispersity, rng);

  // Square lattice of spacing ≥ 1.2·d_max (stretched in x to fit lx exactly). Each
  // coordinate is jittered by at most 0.4 of the free gap spacing − d_max, so that
  // neighbours, the base and the periodic images stay strictly apart.
  const double spacing = 1.2 * d_max;
  const std::int64_t columns = std::max<std::int64_t>(1, std::int64_t(lx / spacing));
  const double ax = lx / double(columns);
  const double jitter = 0.4 * (spacing - d_max);
  const double y0 = base_top + 0.5 * spacing;
  double top = base_top;
  for (std::int64_t k = 0; k < mobile; ++k) {
    const double jx = rng.uniform(-jitter, jitter);
    const double jy = rng.uniform(-jitter, jitter);
    const Vec2 r((double(k % columns) + 0.5) * ax + jx, y0 + double(k / columns) * spacing + jy);
    out.position.push_back(r);
    out.radius.push_back(radius[std::size_t(k)]);
    top = std::max(top, r.y() + radius[std::size_t(k)]);
  }

  out.box = Box{lx, top + sigma, false, 0.0};
  out.fixed.assign(out.radius.size(), 0);
  std::fill(out.fixed.begin(), out.fixed.begin() + std::ptrdiff_t(base), 1);
  double mobile_area = 0;
  for (double r : radius) mobile_area += M_PI * r * r;
  out.packing_fraction = mobile_area / (lx * (top - base_top));
  out.max_overlap = max_overlap(out.box, out.position, out.radius);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace granflow
