#pragma once
// Depth profiles of incline flow (thesis §4.3.1, Figs 4.8–4.9): fields averaged over x
// and over time in layers [kΔy, (k+1)Δy) above the base centre line y = 0.
//
// Coarse graining (eq. 2.4–2.8) with G = indicator of the layer / (Lx·Δy):
// - mass and momentum of the mobile grains assigned by their centres; V = Σmv/Σm;
// - kinetic stress Σ m (v − V)⊗(v − V) and temperature (eq. 4.5) N·T = Σ|v − V|² +
//   ½ΣR²(ω − Ω)², both about the layer's mean velocity of the same sample (mass-
//   weighted for the stress, plain for T as in eq. 4.5) *and* its mean shear inside the
//   layer: v_x − V_x − γ̇(y − ȳ), γ̇ the time-averaged shear rate of the layer. Without
//   the last term a layer of thickness Δy would count the mean flow across it as heat,
//   (γ̇Δy)²/12, as large as T itself for Δy = 3σ;
// - contact stress (eq. 2.8): each contact once, the segment between its grains'
//   centres split among the layers it crosses, F_α b_β times the fraction of the
//   segment in the layer (b = r_i − r_j, F the force on i);
// - packing fraction: exact area of all disks (the base's included) inside the layer
//   (circular segments) over Lx·Δy.
// Stress components follow eq. 2.2: Σ_αβ is the flux of α-momentum along β, so the
// contact part of Σ_xy is F_x b_y: what carries x-momentum through horizontal lines.
// It is the transpose of σ⊗F in shear/observables.hpp (the same for frictionless
// grains, and in a time average with friction, where torques balance). Compression is
// positive; p = (Σxx + Σyy)/2 and the shear stress s = −Σxy is positive for flow down
// the slope.
//
// Momentum balance (eq. 4.7): averaged over a layer, the flux through the horizontal
// line at height y balances the weight above it, so in a steady time average
//   Σ_yy = g cos θ · W,  s = g sin θ · W,
// W = layer average of (1/Lx)·Σ_{i: y_i > y} m_i (point masses), up to the fluctuations
// of each layer's mean velocity, which the kinetic stress leaves out (~1/N_layer of it).
//
// Samples are summed into time blocks of a fixed number of steps, kept so that the
// steady part can be chosen afterwards and profiles re-analysed from the stored blocks.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "dynamics/engine.hpp"
#include "dynamics/grains.hpp"
#include "geometry/box.hpp"

namespace granflow {

// Area of the disk of radius r centred at height yc between the heights a ≤ b.
double disk_strip_area(double yc, double r, double a, double b);

// Layers [kΔy, (k+1)Δy), k < bins, in a box of width lx.
struct ProfileGrid {
  double bin = 0;  // Δy
  int bins = 0;
  double lx = 0;

  double layer_area() const { return lx * bin; }
};

// The layers of thickness bin > 0 that cover [0, ly] of a box open in y.
ProfileGrid profile_grid(const Box& box, double bin);

// The per-layer sums a sample adds to its block; per grain in the layer unless said.
enum ProfileColumn : int {
  kGrains,           // mobile grains
  kMass,             // Σ m
  kMomentumX,        // Σ m v_x
  kMomentumY,        // Σ m v_y
  kFluctuationXX,    // Σ (v_x − v̄_x)², v̄ the layer's plain mean velocity in the sample
  kFluctuationYY,    // Σ (v_y − v̄_y)²
  kFluctuationXH,    // Σ (v_x − v̄_x)(y − ȳ), ȳ the layer's plain mean height
  kFluctuationHH,    // Σ (y − ȳ)²
  kFluctuationSpin,  // Σ R²(ω − ω̄)²
  kKineticXX,        // Σ m (v_x − V_x)², V the layer's mass-weighted mean velocity
  kKineticXY,        // Σ m (v_x − V_x)(v_y − V_y)
  kKineticYY,        // Σ m (v_y − V_y)²
  kKineticXH,        // Σ m (v_x − V_x)(y − Y), Y the mass-weighted mean height
  kKineticYH,        // Σ m (v_y − V_y)(y − Y)
  kKineticHH,        // Σ m (y − Y)²
  kContactXX,        // Σ_contacts F_x b_x · fraction of the branch segment in the layer
  kContactXY,        // Σ F_x b_y · fraction
  kContactYX,        // Σ F_y b_x · fraction
  kContactYY,        // Σ F_y b_y · fraction
  kArea,             // area of all disks (fixed ones included) inside the layer
  kMassAbove,        // layer average over y of Σ_{mobile i: y_i > y} m_i
  kProfileColumns
};

struct ProfileColumnInfo {
  const char* name;
  const char* meaning;
  const char* units;
};
// Name (dataset name of the stored blocks), meaning and units of each column.
const ProfileColumnInfo& profile_column(int column);

// Bulk observables of the mobile grains, recorded at every observed step.
struct InclineObservables {
  double flow_rate = 0;       // mass-weighted mean v_x (down the slope)
  double kinetic_energy = 0;  // Σ ½mv² + ½Iω²
  double height = 0;          // centre-of-mass height
};
InclineObservables incline_observables(const GrainState& state);

// One time block: the steps (index·B, (index+1)·B].
struct ProfileBlock {
  std::int64_t index = 0;
  std::int64_t samples = 0;
  double time_begin = 0, time_end = 0;  // times of its first and last sample
  InclineObservables observables;       // summed over the samples
  std::vector<double> sums;             // [column][bin], summed over the samples
};

// The steps per block of --profile-block 0 (automatic) for a run of `steps` steps:
// min(5000, steps/20), at least 1. Runs of 10⁵ steps or more keep blocks of 5000 steps;
// a shorter run still gets at least 20 full blocks (all of its steps when it has fewer
// than 20), what the steady-state detection (MSER, d ≤ n/2, and the halves check)
// needs to have anything to choose from.
std::int64_t automatic_profile_block(std::int64_t steps);

class ProfileAccumulator {
 public:
  ProfileAccumulator(ProfileGrid grid, std::int64_t block_steps);

  // Adds the state after step `step` (≥ 1) at `time` (in the unit the blocks keep:
  // gf-incline's τ), the contacts of that step and its observables
  // (incline_observables). Mobile grains must lie in [0, ly] (check_layer).
  void add(std::int64_t step, double time, const GrainState& state, const ContactRecords& contacts,
           const InclineObservables& observables);

  const ProfileGrid& grid() const { return grid_; }
  std::int64_t block_steps() const { return block_steps_; }
  const std::vector<ProfileBlock>& blocks() const { return blocks_; }
  // Continues after the blocks of a checkpoint (same grid and block length).
  void restore(std::vector<ProfileBlock> blocks) { blocks_ = std::move(blocks); }

 private:
  ProfileGrid grid_;
  std::int64_t block_steps_;
  std::vector<ProfileBlock> blocks_;
  // Work space of one sample.
  std::vector<int> layer_;
  std::vector<double> count_, mass_, height_, mass_height_, spin_;
  std::vector<Vec2> velocity_, momentum_;
};

// Time-averaged profiles over a set of blocks, bins up to the highest that ever held a
// mobile grain. Undefined values (no grain in a layer) are NaN.
struct Profiles {
  std::vector<double> y;  // layer centres
  std::vector<double> packing_fraction;
  std::vector<double> velocity_x;  // Σmv_x / Σm over all samples
  // dV_x/dy, central differences between the nearest layers holding grains (one-sided
  // at the ends).
  std::vector<double> shear_rate;
  std::vector<double> temperature;                      // eq. 4.5, about V and the mean shear inside the layer
  std::vector<double> stress_xx, stress_xy, stress_yy;  // kinetic + contact
  std::vector<double> pressure;                         // (Σxx + Σyy)/2
  std::vector<double> shear_stress;                     // −Σxy
  std::vector<double> weight_above;                     // g · W (see above)
  // Bagnold invariants (§4.3.2), ratios of the time averages:
  std::vector<double> s_over_p;     // s/p
  std::vector<double> inertial;     // γ̇⟨R⟩/√T
  std::vector<double> mT_over_pR2;  // m T / (p ⟨R⟩²)
  std::int64_t samples = 0;
};

// g: magnitude of gravity; mean_radius, mean_mass: ⟨R⟩ and m of the mobile grains.
Profiles average_profiles(const ProfileGrid& grid, const std::vector<ProfileBlock>& blocks, std::size_t first, double g,
                          double mean_radius, double mean_mass);

}  // namespace granflow
