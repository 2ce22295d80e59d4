#pragma once
// The contacts of one step or stored frame, one row each: what the engine reports and
// what /particles/grains/contacts holds (docs/file-format.md, Contacts), in one type so that neither side
// converts.
#include <array>
#include <cstdint>
#include <vector>

#include "core/vec.hpp"

namespace granflow {

// Contacts with P_n > 0, sorted by (i, j).
struct ContactRecords {
  std::vector<std::array<std::int32_t, 2>> pair;  // (i, j) with i < j
  std::vector<double> normal_force;               // P_n/dt ≥ 0, on i along n̂
  std::vector<double> tangential_force;           // P_t/dt, on i along t̂ = perp(n̂)
  std::vector<Vec2> branch;                       // r_i − r_j (minimum image), n̂ = branch/|branch|
  // Force of the same pair as an isolated binary collision (eq. 5.4, A.5):
  // (1 + e)·m_ij·max(0, −u_n⁻)/dt, m_ij the reduced mass (m_i for a fixed partner).
  std::vector<double> binary_force;
  std::vector<std::array<double, 2>> pre_normal_velocity;  // ṽ_i·n̂, ṽ_j·n̂ before the step
  // Consecutive steps, this one included, in which the pair had P_n > 0 (1: new contact;
  // ≥ 2: "long-lived" in the sense of §6.2.2).
  std::vector<std::int64_t> age;

  std::size_t size() const { return pair.size(); }
  void clear() {
    pair.clear();
    normal_force.clear();
    tangential_force.clear();
    branch.clear();
    binary_force.clear();
    pre_normal_velocity.clear();
    age.clear();
  }
};

}  // namespace granflow
