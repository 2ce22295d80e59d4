#pragma once
// The contact rows of a step: one local problem per candidate pair (normal, bounds,
// reduced mass, impulses), the bodies the impulses act on, the warm start from the
// previous step's contacts and the records of this step's. The solvers (GaussSeidel,
// ClusterSolver) work on the rows and bodies held here.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/contact_records.hpp"
#include "core/vec.hpp"
#include "dynamics/broad_phase.hpp"
#include "dynamics/contact_law.hpp"
#include "dynamics/grains.hpp"
#include "dynamics/tiling.hpp"
#include "geometry/box.hpp"

namespace granflow {

// Hot data of the Gauss–Seidel loop: 48 bytes per contact for the normal law, and with
// friction 16 more in a separate array, which the frictionless path (the default) never
// reads or writes. Bodies hold s = R·ω so that u_t needs no radii (ΔS = −2·P_t/m for
// I = mR²/2). Bodies are in the internal spatial order (see Tiling), so neighbouring
// contacts touch nearby memory.
struct alignas(32) Body {
  double vx, vy, spin, inv_mass;
};
struct alignas(16) Row {
  int i, j;  // bodies of grains i < j
  double nx, ny;
  double bn;     // bound on the raw (v_i − v_j)·n̂
  double inv_w;  // 1/W_nn = reduced mass; 1/W_tt = inv_w/3
  double pn;
};
struct Tangent {
  double bt;  // bound on the raw (v_i − v_j)·t̂ − s_i − s_j
  double pt;
};

// Per-row flags of the frictionless solvers: still corrected by Υ or more in the last sweep
// (hot); carrying P_n > 0 (bearing).
constexpr std::uint8_t kHot = 1, kBearing = 2;

// What the rows of a step are built from and recorded against: the engine's state before
// the step and its parameters.
struct StepInput {
  const GrainState& state;
  const Box& box;
  double rate, dt;
  const Material& material;
  Vec2 gravity;
  int threads;
  Activation activation;
};

// Key of the pair of grains i < j: (i << 32) | j, in the candidates' order.
inline std::uint64_t pair_key(int i, int j) { return (std::uint64_t(std::uint32_t(i)) << 32) | std::uint32_t(j); }

class ContactRows {
 public:
  explicit ContactRows(std::size_t grains = 0) : bodies_(grains) {}

  // The rows of the candidates, stored in sweep order (see Tiling::sort_rows()), warm-started
  // from the previous step's contacts.
  void build(const StepInput& in, const std::vector<Candidate>& candidates, Tiling& tiling);
  // Bodies at the free velocities, plus the warm-start impulses.
  void load_bodies(const StepInput& in, const Tiling& tiling);
  // The bodies' velocities back into the grain state.
  void store_bodies(GrainState& s, const Tiling& tiling, int threads) const;
  // Records the contacts of this step (rows with P_n > 0; where flags are given, those whose
  // flags have the bit `bearing`), in candidate order, and keeps them for the next step's
  // warm start. Returns this step's tallies (see StepReport), summed in candidate order.
  struct Tally {
    int collisions = 0;
    double collision_velocity_product = 0, dissipated_energy = 0;
  };
  Tally record(const StepInput& in, const std::vector<Candidate>& candidates, const std::uint8_t* flags,
               std::uint8_t bearing);

  std::size_t size() const { return rows_.size(); }
  std::vector<Row>& rows() { return rows_; }
  const std::vector<Row>& rows() const { return rows_; }
  std::vector<Tangent>& tangents() { return tangents_; }  // per row with friction; empty without
  const std::vector<Tangent>& tangents() const { return tangents_; }
  std::vector<Body>& bodies() { return bodies_; }
  const std::vector<Body>& bodies() const { return bodies_; }
  // Per row: its mobile bodies (−1: fixed), compact for the cluster passes.
  const std::vector<std::array<int, 2>>& row_bodies() const { return row_bodies_; }
  const ContactRecords& records() const { return records_; }

  // The memory of the last step (what the next one is warm-started from): pair keys, sorted,
  // with the forces and ages recorded; set_memory() replaces it (a restart).
  const std::vector<std::uint64_t>& memory_keys() const { return prev_key_; }
  const std::vector<double>& memory_normal_force() const { return prev_fn_; }
  const std::vector<double>& memory_tangential_force() const { return prev_ft_; }
  const std::vector<int>& memory_age() const { return prev_age_; }
  void set_memory(std::vector<std::uint64_t> keys, std::vector<double> normal_force,
                  std::vector<double> tangential_force, std::vector<int> age);

  std::size_t bytes() const;

 private:
  void build_row(const StepInput& in, const std::vector<Candidate>& candidates, const Tiling& tiling, std::size_t c,
                 std::size_t& p);
  double dissipated(const StepInput& in, const Row& r, std::size_t c, int i, int j, double shift) const;

  std::vector<int> row_of_;  // candidate → row (sweep order)
  std::vector<Body> bodies_;
  std::vector<Row> rows_;
  std::vector<Tangent> tangents_;
  std::vector<std::array<int, 2>> row_bodies_;
  std::vector<int> row_age_;  // per candidate: age of the matched contact of the previous step, else 0

  // Memory of the previous step, sorted by key = (i << 32) | j.
  std::vector<std::uint64_t> prev_key_;
  std::vector<double> prev_fn_, prev_ft_;  // forces, as recorded
  std::vector<int> prev_age_;

  ContactRecords records_;
  std::vector<double> dissipated_;        // per recorded contact: its share of dissipated_energy
  std::vector<std::size_t> chunk_start_;  // record(): first contact of each chunk of candidates
};

}  // namespace granflow
