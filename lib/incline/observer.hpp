#pragma once
// What gf-incline records: bulk observables at every observed step; profile samples at
// every step, summed into time blocks (kept across checkpoints); and at the end the
// steady part and its time-averaged depth profiles in /profiles.
//
// Profiles sample every step, not every observed one: contact stresses are sums of
// impulses, each collision acts during one step only, and a sample costs less than one
// solver sweep; sampling every 10th step left a 4 % noise on the stress of the layer
// next to the base (where collisions with the base dominate) after 5·10⁴ steps.
//
// Output layout:
//   /observables/{flow_rate, kinetic_energy, height}   H5MD elements (see InclineObservables)
//   /profiles/<name> [layers]     time-averaged profiles (Profiles), attributes meaning, units;
//                                 group attributes: steady, steady_from_step/_time, time_unit, ...
// Every time (block times, steady_from_time, mser_*_time) is in τ, the unit of the
// options and of the trajectory's own time datasets; only rates and velocities keep
// code units.
//   /profiles/blocks/<column> [blocks][bins]   per-block sums (ProfileColumn, with meaning, units)
//   /profiles/blocks/{index, samples, time_begin, time_end} [blocks]
//   /profiles/blocks/{flow_rate, kinetic_energy, height} [blocks]   observables summed per block
#include <optional>
#include <string>
#include <vector>

#include "dynamics/engine.hpp"
#include "incline/profiles.hpp"
#include "io/trajectory.hpp"
#include "statistics/steady.hpp"

namespace granflow {

// After every step: fails if a grain left the layer (check_layer), then adds the step to
// the profile blocks at the engine's time in `unit` (the output's: gf-incline's τ), as
// io::TrajectoryWriter stores it.
void sample_incline(const Engine& engine, ProfileAccumulator& profiles, const io::TimeUnit& unit = {});
// At every observed step: flow_rate, kinetic_energy and height in /observables.
void record_incline_observables(const Engine& engine, io::TrajectoryWriter& writer);

// The blocks as datasets of `group` (layout above), and back (UsageError naming the file
// if they do not fit the grid).
void write_blocks(io::TrajectoryWriter& writer, const std::string& group, const ProfileAccumulator& profiles);
std::vector<ProfileBlock> read_blocks(const io::TrajectoryReader& reader, const std::string& group,
                                      const ProfileGrid& grid);

// Constants of the run the analysis needs.
struct InclineUnits {
  double dt = 0;
  double tau = 0;          // √(⟨R⟩/g), in code time
  double gravity = 0;      // g
  double mean_radius = 0;  // ⟨R⟩ of the mobile grains
  double mean_mass = 0;

  // Step n's time in τ.
  double time_of_step(std::int64_t step) const { return double(step) * dt / tau; }
};

struct ProfileAnalysis {
  SteadyState steady;          // first: first block averaged
  bool chosen = false;         // the start was given (--from-time), not detected
  std::int64_t from_step = 0;  // where the averaged blocks start
  Profiles profiles;
};

// The steady part, detected (detect_steady on the block means of flow_rate and
// kinetic_energy over the full blocks; only the last block can be short) or from the
// first block whose first sample is at or after from_time (τ, as the blocks' times),
// and its profiles.
ProfileAnalysis analyse_profiles(const ProfileAccumulator& profiles, const InclineUnits& units,
                                 std::optional<double> from_time);

// /profiles and /profiles/blocks (layout above).
void write_profiles(io::TrajectoryWriter& writer, const ProfileAccumulator& profiles, const ProfileAnalysis& analysis,
                    const InclineUnits& units);

// One line on stderr: where the steady part starts and how much of it was averaged, or,
// always (quiet or not), a warning that the run did not reach a steady state.
void report_steady(const char* program, const ProfileAccumulator& profiles, const ProfileAnalysis& analysis,
                   const InclineUnits& units, bool quiet);

}  // namespace granflow
