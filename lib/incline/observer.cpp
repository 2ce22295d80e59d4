#include "incline/observer.hpp"

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
#include "incline/start.hpp"

namespace granflow {

namespace {

// Observables summed per block, in InclineObservables order.
constexpr const char* kBlockObservables[] = {"flow_rate", "kinetic_energy", "height"};

double& observable(InclineObservables& o, int k) { return k == 0 ? o.flow_rate : k == 1 ? o.kinetic_energy : o.height; }

io::Parameters described(const std::string& meaning, const std::string& units) {
  io::Parameters p;
  p.set("meaning", meaning);
  p.set("units", units);  // TrajectoryWriter::write_array adds its H5MD `unit`
  return p;
}

}  // namespace

void sample_incline(const Engine& engine, ProfileAccumulator& profiles, const io::TimeUnit& unit) {
  check_layer(engine.state(), engine.box(), engine.step_count());
  profiles.add(engine.step_count(), engine.time() / unit.code_per_unit, engine.state(), engine.contacts(),
               incline_observables(engine.state()));
}

void record_incline_observables(const Engine& engine, io::TrajectoryWriter& writer) {
  const std::int64_t step = engine.step_count();
  const double time = engine.time();
  const InclineObservables o = incline_observables(engine.state());
  writer.append_observable("flow_rate", step, time, o.flow_rate);
  writer.append_observable("kinetic_energy", step, time, o.kinetic_energy);
  writer.append_observable("height", step, time, o.height);
}

void write_blocks(io::TrajectoryWriter& writer, const std::string& group, const ProfileAccumulator& profiles) {
  const auto& blocks = profiles.blocks();
  const std::size_t n = blocks.size(), bins = std::size_t(profiles.grid().bins);
  for (int c = 0; c < kProfileColumns; ++c) {
    std::vector<double> values;
    values.reserve(n * bins);
    for (const ProfileBlock& b : blocks) {
      const auto first = b.sums.begin() + std::ptrdiff_t(c * bins);
      values.insert(values.end(), first, first + std::ptrdiff_t(bins));
    }
    const ProfileColumnInfo& info = profile_column(c);
    writer.write_array(
        group + "/" + info.name, {n, bins}, values,
        described(std::string(info.meaning) + "; summed over the block's samples (divide by samples)", info.units));
  }
  std::vector<double> index, samples, begin, end, summed[3];
  for (const ProfileBlock& b : blocks) {
    index.push_back(double(b.index));
    samples.push_back(double(b.samples));
    begin.push_back(b.time_begin);
    end.push_back(b.time_end);
    summed[0].push_back(b.observables.flow_rate);
    summed[1].push_back(b.observables.kinetic_energy);
    summed[2].push_back(b.observables.height);
  }
  auto column = [&](const char* name, const std::vector<double>& values, const std::string& meaning,
                    const std::string& units) {
    writer.write_array(group + "/" + name, {n}, values, described(meaning, units));
  };
  column("index", index, "block number k: the steps in (k·block_steps, (k+1)·block_steps]", "1");
  column("samples", samples, "steps summed in the block", "1");
  column("time_begin", begin, "time of the block's first sample", "tau");
  column("time_end", end, "time of the block's last sample", "tau");
  column("flow_rate", summed[0], "mass-weighted mean v_x of the mobile grains, summed over the block's samples",
         "velocity");
  column("kinetic_energy", summed[1], "Σ ½mv² + ½Iω² of the mobile grains, summed over the block's samples",
         "mass·velocity²");
  column("height", summed[2], "centre-of-mass height of the mobile grains, summed over the block's samples", "length");
}

std::vector<ProfileBlock> read_blocks(const io::TrajectoryReader& reader, const std::string& group,
                                      const ProfileGrid& grid) {
  const std::size_t bins = std::size_t(grid.bins);
  std::vector<std::size_t> shape;
  const std::vector<double> index = reader.array(group + "/index", &shape);
  const std::size_t n = index.size();
  auto bad = [&](const std::string& name) {
    return UsageError("'" + reader.path() + "': " + group + "/" + name + " does not match the run's " +
                      std::to_string(n) + " blocks of " + std::to_string(bins) + " layers");
  };
  std::vector<ProfileBlock> blocks(n);
  for (std::size_t b = 0; b < n; ++b) {
    blocks[b].index = std::int64_t(index[b]);
    blocks[b].sums.resize(kProfileColumns * bins);
  }
  auto column = [&](const char* name) {
    std::vector<double> values = reader.array(group + "/" + name, &shape);
    if (shape != std::vector<std::size_t>{n}) throw bad(name);
    return values;
  };
  const std::vector<double> samples = column("samples"), begin = column("time_begin"), end = column("time_end");
  for (std::size_t b = 0; b < n; ++b) {
    blocks[b].samples = std::int64_t(samples[b]);
    blocks[b].time_begin = begin[b];
    blocks[b].time_end = end[b];
  }
  for (int k = 0; k < 3; ++k) {
    const std::vector<double> values = column(kBlockObservables[k]);
    for (std::size_t b = 0; b < n; ++b) observable(blocks[b].observables, k) = values[b];
  }
  for (int c = 0; c < kProfileColumns; ++c) {
    const char* name = profile_column(c).name;
    const std::vector<double> values = reader.array(group + "/" + name, &shape);
    if (shape != std::vector<std::size_t>{n, bins}) throw bad(name);
    for (std::size_t b = 0; b < n; ++b)
      std::copy_n(values.begin() + std::ptrdiff_t(b * bins), bins, blocks[b].sums.begin() + std::ptrdiff_t(c * bins));
  }
  return blocks;
}

ProfileAnalysis analyse_profiles(const ProfileAccumulator& profiles, const InclineUnits& units,
                                 std::optional<double> from_time) {
  const auto& blocks = profiles.blocks();
  ProfileAnalysis a;
  std::vector<std::vector<double>> series(2);
  for (const ProfileBlock& b : blocks) {
    if (b.samples < profiles.block_steps()) continue;  // the last one, if the run ends inside it
    series[0].push_back(b.observables.flow_rate / double(b.samples));
    series[1].push_back(b.observables.kinetic_energy / double(b.samples));
  }
  if (from_time) {
    a.chosen = true;
    std::size_t first = 0;
    while (first + 1 < blocks.size() && blocks[first].time_begin < *from_time) ++first;
    a.steady = steady_from(series, first);
  } else {
    a.steady = detect_steady(series);
  }
  a.from_step = blocks[a.steady.first].index * profiles.block_steps();
  a.profiles =
      average_profiles(profiles.grid(), blocks, a.steady.first, units.gravity, units.mean_radius, units.mean_mass);
  return a;
}

void write_profiles(io::TrajectoryWriter& writer, const ProfileAccumulator& profiles, const ProfileAnalysis& analysis,
                    const InclineUnits& units) {
  const Profiles& p = analysis.profiles;
  const std::size_t layers = p.y.size();
  const std::string stress = "force/length (2D stress)";
  auto write = [&](const char* name, const std::vector<double>& values, const std::string& meaning,
                   const std::string& units_text) {
    writer.write_array(std::string("/profiles/") + name, {layers}, values, described(meaning, units_text));
  };
  write("y", p.y, "height of the layer's centre above the base centre line y = 0", "length");
  write("packing_fraction", p.packing_fraction, "area of the disks inside the layer / layer area", "1");
  write("velocity_x", p.velocity_x, "V_x = Σmv_x/Σm of the mobile grains with centre in the layer", "velocity");
  write("shear_rate", p.shear_rate,
        "dV_x/dy by central differences between the nearest layers holding grains (one-sided at the ends)", "1/time");
  write("temperature", p.temperature,
        "T of eq. 4.5 per layer, about the layer's mean velocity and its mean shear inside the layer", "velocity²");
  write("stress_xx", p.stress_xx, "Σxx, kinetic + contact (eq. 2.7, layer coarse graining)", stress);
  write("stress_yy", p.stress_yy, "Σyy, kinetic + contact", stress);
  write("stress_xy", p.stress_xy, "Σxy: flux of x-momentum through horizontal lines, kinetic + contact", stress);
  write("pressure", p.pressure, "p = (Σxx + Σyy)/2", stress);
  write("shear_stress", p.shear_stress, "s = −Σxy (positive for flow down the slope)", stress);
  write("weight_above", p.weight_above,
        "g × layer average over y of (1/Lx)·Σ m_i over mobile grains with y_i > y: momentum balance "
        "predicts Σyy = cos θ × this and s = sin θ × this",
        stress);
  write("s_over_p", p.s_over_p, "s/p (ratio of the time averages)", "1");
  write("inertial", p.inertial, "γ̇⟨R⟩/√T (ratio of the time averages)", "1");
  write("mT_over_pR2", p.mT_over_pR2, "m T/(p⟨R⟩²), m and ⟨R⟩ the mobile grains' mean mass and radius", "1");

  const auto& blocks = profiles.blocks();
  auto block_start = [&](std::size_t b) { return units.time_of_step(blocks[b].index * profiles.block_steps()); };
  io::Parameters a;
  a.set("steady", analysis.steady.steady ? 1 : 0);
  a.set("steady_from_given", analysis.chosen ? 1 : 0);
  a.set("steady_from_step", analysis.from_step);
  a.set("steady_from_time", units.time_of_step(analysis.from_step));
  a.set("time_unit", "tau");
  for (std::size_t k = 0; k < analysis.steady.truncation.size(); ++k)
    a.set(std::string("mser_") + kBlockObservables[k] + "_time", block_start(analysis.steady.truncation[k]));
  a.set("blocks", std::int64_t(blocks.size()));
  a.set("blocks_averaged", std::int64_t(blocks.size() - analysis.steady.first));
  a.set("samples", p.samples);
  a.set("block_steps", profiles.block_steps());
  a.set("bin", profiles.grid().bin);
  a.set("layer_length", profiles.grid().lx);
  a.set("tau", units.tau);
  a.set("gravity", units.gravity);
  a.set("mean_radius", units.mean_radius);
  a.set("mean_mass", units.mean_mass);
  a.set("method",
        "steady part: MSER truncation (White 1997, d <= n/2) of the block means of flow_rate and kinetic_energy, "
        "the later one, unless --from-time; steady = both series' first- and second-half means of the remaining "
        "full blocks agree within 3 standard errors; profiles are averages over the blocks from there");
  writer.write_attributes("/profiles", a);
  write_blocks(writer, "/profiles/blocks", profiles);
}

void report_steady(const char* program, const ProfileAccumulator& profiles, const ProfileAnalysis& analysis,
                   const InclineUnits& units, bool quiet) {
  const double from = units.time_of_step(analysis.from_step);
  const std::size_t averaged = profiles.blocks().size() - analysis.steady.first;
  if (!analysis.steady.steady)
    std::fprintf(stderr,
                 "%s: warning: no steady state: flow_rate or kinetic_energy still drifts after t = %.4g τ "
                 "(/profiles has steady = 0 and averages the %zu blocks from there)\n",
                 program, from, averaged);
  else if (!quiet)
    std::fprintf(stderr, "%s: steady from t = %.4g τ (%s); /profiles averages %zu blocks (%.4g τ)\n", program, from,
                 analysis.chosen ? "--from-time" : "MSER", averaged,
                 double(analysis.profiles.samples) * units.dt / units.tau);
}

}  // namespace granflow
