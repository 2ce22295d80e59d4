#include "shear/shear.hpp"

#include <cmath>
#include <cstdio>

#include "core/error.hpp"
#include "core/random.hpp"
#include "packing/start_check.hpp"
#include "run/frames.hpp"
#include "shear/observables.hpp"

namespace granflow {
namespace {

bool at_rest(const GrainState& s) {
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.velocity[i] != Vec2::Zero() || s.angular_velocity[i] != 0) return false;
  return true;
}

// Gaussian velocities, zero total momentum, ω = 0, scaled to T exactly.
void thermalise(GrainState& s, const Box& box, double temperature, std::uint64_t seed) {
  Rng rng(seed);
  Vec2 momentum = Vec2::Zero();
  double mass = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double vx = rng.normal();
    s.velocity[i] = Vec2(vx, rng.normal());
    momentum += s.mass[i] * s.velocity[i];
    mass += s.mass[i];
  }
  for (auto& v : s.velocity) v -= momentum / mass;
  const double scale = std::sqrt(temperature / granular_temperature(s, box, 0.0));
  for (auto& v : s.velocity) v *= scale;
}

}  // namespace

BranchVelocities branch_velocities_named(const std::string& name) {
  if (name == "scale") return BranchVelocities::scale;
  if (name == "keep") return BranchVelocities::keep;
  if (name == "reset") return BranchVelocities::reset;
  throw UsageError("option --branch-velocities: must be scale, keep or reset, not '" + name + "'");
}

void branch_velocities(GrainState& state, const Box& box, double source_rate, double rate, BranchVelocities mode) {
  switch (mode) {
    case BranchVelocities::scale: {
      if (source_rate == rate) return;
      const double a = rate / source_rate;
      for (std::size_t i = 0; i < state.size(); ++i) {
        if (state.fixed[i]) continue;
        state.velocity[i] *= a;
        state.angular_velocity[i] *= a;
      }
      return;
    }
    case BranchVelocities::keep:
      if (source_rate == rate) return;
      remove_affine_flow(state, box, source_rate);
      add_affine_flow(state, box, rate);
      return;
    case BranchVelocities::reset:
      for (std::size_t i = 0; i < state.size(); ++i) {
        if (state.fixed[i]) continue;
        state.velocity[i] = Vec2::Zero();
        state.angular_velocity[i] = 0;
      }
      add_affine_flow(state, box, rate);
      return;
  }
}

ShearStart shear_start(const io::TrajectoryReader& input, long long frame_index, double rate, double temperature,
                       std::uint64_t seed, std::optional<BranchVelocities> mode) {
  const std::string& path = input.path();
  const std::size_t index = input.frame_index(frame_index);
  io::Frame frame = input.frame(index);
  io::GrainProperties properties = input.grains();
  if (!frame.box.periodic_y) throw UsageError("'" + path + "' is an incline packing (box open in y): use gf-incline");
  for (auto f : properties.fixed)
    if (f) throw UsageError("'" + path + "' has fixed grains: simple shear needs a biperiodic packing");
  require_run_contacts(input);
  check_start_grains(path, index, frame.box, frame.position, properties.radius);

  ShearStart start;
  start.box = frame.box;
  start.grains = grains_of(frame, properties);
  if (at_rest(start.grains)) {
    if (mode)
      throw UsageError("option --branch-velocities cannot be combined with a start from a frame at rest ('" + path +
                       "' frame " + std::to_string(index) + ", a packing): it has no velocities to branch");
    start.fresh = true;
    if (rate != 0) {
      add_affine_flow(start.grains, start.box, rate);
    } else {
      if (!(temperature > 0))
        throw UsageError("'" + path + "' is at rest: with --rate 0 give --temperature T0 > 0 to start it");
      thermalise(start.grains, start.box, temperature, seed);
    }
    return start;
  }
  if (frame.has_contacts) {
    check_start_contacts(path, index, frame.contacts);
    start.contacts = frame.contacts;
  }
  const double source_rate = input.lees_edwards_rate();
  const BranchVelocities rule = mode.value_or(BranchVelocities::scale);
  if (rule == BranchVelocities::reset && rate == 0)
    throw UsageError("option --branch-velocities: reset at --rate 0 would leave every grain at rest");
  if (source_rate != rate && (source_rate == 0 || rate == 0))
    throw UsageError("'" + path + "' was run at rate " + std::to_string(source_rate) + ": branching to rate " +
                     std::to_string(rate) + " is only possible between non-zero rates (start from a packing instead)");
  branch_velocities(start.grains, start.box, source_rate, rate, rule);
  if (source_rate != rate) {
    // In every mode: the contacts only warm-start the first solve. Every force column
    // scales as γ̇² (binary forces too); velocities as γ̇.
    const double a = rate / source_rate;
    for (auto& f : start.contacts.normal_force) f *= a * a;
    for (auto& f : start.contacts.tangential_force) f *= a * a;
    for (auto& f : start.contacts.binary_force) f *= a * a;
    for (auto& v : start.contacts.pre_normal_velocity) v = {v[0] * a, v[1] * a};
  }
  return start;
}

namespace {
const std::string kTally = "/shear_tally";
}

void ShearTally::add(const StepReport& report) {
  collisions += report.collisions;
  collision_velocity_product += report.collision_velocity_product;
  dissipated_energy += report.dissipated_energy;
  ++steps;
}

void ShearTally::write(io::TrajectoryWriter& checkpoint) const {
  io::Parameters p;
  p.set("collisions", collisions);
  p.set("collision_velocity_product", collision_velocity_product);
  p.set("dissipated_energy", dissipated_energy);
  p.set("steps", steps);
  checkpoint.write_attributes(kTally, p);
}

void ShearTally::restore(const io::TrajectoryReader& checkpoint) {
  const io::Parameters p = checkpoint.attributes(kTally);
  if (!p.has("collisions") || !p.has("collision_velocity_product") || !p.has("dissipated_energy") || !p.has("steps"))
    throw UsageError("checkpoint '" + checkpoint.path() + "' holds no collision and dissipation tally (" + kTally +
                     "): it was written by an older gf-shear; run without --resume to start over");
  collisions = p.get_int("collisions");
  collision_velocity_product = p.get_double("collision_velocity_product");
  dissipated_energy = p.get_double("dissipated_energy");
  steps = p.get_int("steps");
}

void record_shear_observables(const Engine& engine, io::TrajectoryWriter& writer, ShearTally& tally) {
  const std::int64_t step = engine.step_count();
  const double time = engine.time();
  const StressTensors s = stress(engine.state(), engine.box(), engine.rate(), engine.contacts());
  const Mat2 total = s.total();
  writer.append_observable("strain", step, time, engine.rate() * time);
  writer.append_observable("pressure", step, time, pressure(total));
  writer.append_observable("shear_stress", step, time, -shear_stress(total));
  writer.append_observable("normal_stress_difference", step, time, normal_stress_difference(total));
  writer.append_observable("temperature", step, time,
                           granular_temperature(engine.state(), engine.box(), engine.rate()));
  writer.append_observable("stress_kinetic", step, time, s.kinetic);
  writer.append_observable("stress_static", step, time, s.contact);
  writer.append_observable("stress_collisional", step, time, s.collisional);
  writer.append_observable("collisions", step, time, double(tally.collisions));
  writer.append_observable("collision_velocity_product", step, time, tally.collision_velocity_product);
  writer.append_observable("dissipated_energy", step, time, tally.dissipated_energy);
  tally = {};
}

double kinetic_energy_about_mean_flow(const GrainState& state, const Box& box, double rate) {
  double energy = 0;
  for (std::size_t i = 0; i < state.size(); ++i) {
    if (state.fixed[i]) continue;
    const double spin = state.radius[i] * (state.angular_velocity[i] + 0.5 * rate);
    energy += 0.5 * state.mass[i] * (fluctuating_velocity(state, box, rate, i).squaredNorm() + 0.5 * spin * spin);
  }
  return energy;
}

void FirstStepEnergy::write(io::TrajectoryWriter& writer) const {
  io::Parameters p;
  p.set("first_step_kinetic_energy_before", before);
  p.set("first_step_kinetic_energy_after", after);
  if (before > 0) p.set("first_step_kinetic_energy_ratio", after / before);
  writer.write_attributes("/run", p);
}

std::string FirstStepEnergy::warning(double rate, const Material& material) const {
  if (rate != 0 || !(before > 0)) return "";
  const double ratio = after / before;
  const bool elastic = material.restitution == 1 && material.friction == 0;
  if (!(ratio - 1 > 1e-9) && !(elastic && std::fabs(ratio - 1) > 0.01)) return "";
  char line[512];
  std::snprintf(line, sizeof line,
                "the first step %s the kinetic energy by a factor %.4g (%.4g -> %.4g) at rate 0%s: the start is "
                "not an equilibrium state (a packing's touching pairs, which Newton's restitution law on "
                "simultaneous contacts does not treat energy-consistently); discard a warm-up run "
                "(docs/method/kinetic.md)",
                ratio > 1 ? "multiplied" : "changed", ratio, before, after, elastic ? ", e = 1, no friction" : "");
  return line;
}

}  // namespace granflow
