#include "network/geometric_contacts.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

#include "neighbours/cell_list.hpp"

namespace granflow::network {

namespace {

std::uint64_t key(std::int32_t i, std::int32_t j) { return (std::uint64_t(std::uint32_t(i)) << 32) | std::uint32_t(j); }

}  // namespace

ContactRecords geometric_contacts(const io::Frame& frame, const std::vector<double>& radius, double gap, double dt,
                                  double rate) {
  if (!(gap >= 0) || !std::isfinite(gap)) throw std::invalid_argument("the contact gap must be finite and >= 0");
  if (!(dt > 0) || !std::isfinite(dt)) throw std::invalid_argument("the time step must be finite and > 0");
  const std::size_t n = frame.position.size();
  if (radius.size() != n || frame.velocity.size() != n)
    throw std::invalid_argument("radii, positions and velocities of different lengths");
  std::unordered_map<std::uint64_t, double> force;
  force.reserve(frame.contacts.size());
  for (std::size_t c = 0; c < frame.contacts.size(); ++c) {
    const auto [i, j] = frame.contacts.pair[c];
    force[key(std::min(i, j), std::max(i, j))] = frame.contacts.binary_force.empty() ? 0.0 : frame.contacts.binary_force[c];
  }
  const double largest = radius.empty() ? 0.0 : *std::max_element(radius.begin(), radius.end());
  CellList cells;
  cells.build(frame.position, frame.box, 2 * largest + gap);
  struct Found {
    std::int32_t i, j;
    Vec2 d;
    bool before;
  };
  std::vector<Found> found;
  const Box& box = frame.box;
  cells.for_each_pair(frame.position, [&](int a, int b, const Vec2& d_ab) {
    const int i = std::min(a, b), j = std::max(a, b);
    const Vec2 d = a == i ? d_ab : Vec2(-d_ab);
    const double contact = radius[i] + radius[j] + gap;
    if (d.squaredNorm() > contact * contact) return;
    // The image row k the minimum image went through, and the branch one step earlier.
    const Vec2 raw = frame.position[i] - frame.position[j];
    const double k = box.periodic_y ? std::round((raw.y() - d.y()) / box.ly) : 0.0;
    const Vec2 relative = frame.velocity[i] - frame.velocity[j] - Vec2(k * rate * box.ly, 0.0);
    const Vec2 before = d - dt * relative;
    found.push_back({i, j, d, before.squaredNorm() <= contact * contact});
  });
  std::sort(found.begin(), found.end(), [](const Found& x, const Found& y) { return x.i != y.i ? x.i < y.i : x.j < y.j; });
  ContactRecords out;
  for (const Found& f : found) {
    out.pair.push_back({f.i, f.j});
    out.branch.push_back(f.d);
    const auto it = force.find(key(f.i, f.j));
    out.binary_force.push_back(it == force.end() ? 0.0 : it->second);
    out.age.push_back(f.before ? 2 : 1);
  }
  return out;
}

}  // namespace granflow::network
