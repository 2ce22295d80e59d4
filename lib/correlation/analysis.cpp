#include "correlation/analysis.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>
#include <utility>

#include "core/error.hpp"
#include "core/progress.hpp"
#include "core/signals.hpp"
#include "correlation/clusters.hpp"
#include "statistics/jackknife.hpp"
#include "statistics/steady.hpp"

namespace granflow::correlation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Strain of every stored frame, from /observables/strain (`strain`, its values): linear in
// the step between the rows around the frame's step, and extended linearly beyond the first
// and last rows (the strain grows linearly with the step at constant rate).
std::vector<double> frame_strains(const io::TrajectoryReader& reader, const std::vector<double>& strain) {
  const std::vector<std::int64_t> steps = reader.observable_step("strain");
  if (steps.empty() || steps.size() != strain.size())
    throw UsageError("'" + reader.path() + "': /observables/strain is empty or its step and value differ in length");
  std::vector<double> out;
  for (std::int64_t s : reader.frame_steps()) {
    if (steps.size() == 1) {
      out.push_back(steps[0] != 0 ? strain[0] * double(s) / double(steps[0]) : strain[0]);
      continue;
    }
    const auto at = std::lower_bound(steps.begin(), steps.end(), s);
    const std::size_t hi = std::clamp<std::size_t>(std::size_t(at - steps.begin()), 1, steps.size() - 1);
    const std::size_t lo = hi - 1;
    const double t = double(s - steps[lo]) / double(steps[hi] - steps[lo]);
    out.push_back(strain[lo] + t * (strain[hi] - strain[lo]));
  }
  return out;
}

PairSums total_of(const std::vector<PairSums>& blocks, const LagGrid& grid) {
  PairSums total(grid);
  for (const auto& b : blocks) total += b;
  return total;
}

struct RunSums {
  std::vector<PairSums> blocks;
  std::vector<double> map;  // empty when not wanted
  BlockSamples normal, binary;
  std::size_t contacts = 0;
};

// Adds one frame's pair sums and map (Correlator or FftCorrelator).
using Accumulate = std::function<void(const LoadedGrains&, PairSums&, std::vector<double>&)>;

// One pass over the run's frames: pair sums per block, the map, and the forces.
RunSums accumulate_run(const Run& run, const LagGrid& grid, const Accumulate& accumulate, int blocks, bool full,
                       const std::function<void()>& done) {
  const std::size_t frames = run.frames.size();
  const std::size_t block_count = std::min<std::size_t>(std::size_t(blocks), frames);
  RunSums s;
  s.blocks.assign(block_count, PairSums(grid));
  if (full) {
    s.map.assign(std::size_t(grid.map_side()) * std::size_t(grid.map_side()), 0.0);
    s.normal.resize(block_count);
    s.binary.resize(block_count);
  }
  for (std::size_t n = 0; n < frames; ++n) {
    check_interrupt();
    const std::size_t k = run.frames[n], b = n * block_count / frames;
    const io::Frame frame = run.reader.frame(k);
    LoadedGrains grains;
    try {
      grains = loaded_grains(frame);
    } catch (const UsageError& e) {
      throw UsageError("'" + run.path + "' frame " + std::to_string(k) + ": " + e.what());
    }
    accumulate(grains, s.blocks[b], s.map);
    s.contacts += frame.contacts.size();
    if (full) {
      s.normal[b].insert(s.normal[b].end(), frame.contacts.normal_force.begin(), frame.contacts.normal_force.end());
      s.binary[b].insert(s.binary[b].end(), frame.contacts.binary_force.begin(), frame.contacts.binary_force.end());
    }
    done();
  }
  if (!(total_of(s.blocks, grid).norm > 0))
    throw UsageError("'" + run.path + "': no contact forces in the " + std::to_string(frames) +
                     " frame(s) at strain >= " + format_number(run.first_strain));
  return s;
}

double xi_error_of(const std::vector<PairSums>& blocks, Density density = Density::area) {
  return jackknife_errors(blocks,
                          [&](const PairSums& s) { return std::vector<double>{correlation_length(s, density)}; })[0];
}

// ξ/ξ_el and its error, the errors of ξ and ξ_el combined in quadrature.
std::pair<double, double> ratio_of(double xi, double xi_error, double el, double el_error) {
  const double ratio = xi / el;
  return {ratio, std::fabs(ratio) * std::hypot(xi_error / xi, el_error / el)};
}

RunResult summarise(const RunSums& s, const LagGrid& grid, const Settings& settings, std::uint64_t seed) {
  RunResult r;
  const PairSums total = total_of(s.blocks, grid);
  r.blocks = int(s.blocks.size());
  r.contacts = s.contacts;
  r.c = isotropic_correlation(total, grid);
  r.c_error = jackknife_errors(s.blocks, [&](const PairSums& x) { return isotropic_correlation(x, grid); });
  r.xi = correlation_length(total);
  r.xi_error = xi_error_of(s.blocks);
  r.xi_truncated = truncated_correlation_length(total);
  r.xi_length = correlation_length(total, Density::length);
  r.xi_length_error = xi_error_of(s.blocks, Density::length);
  r.xi_length_truncated = truncated_correlation_length(total, Density::length);
  r.xi_theta = angular_correlation_length(total, grid);
  r.xi_theta_error = jackknife_errors(s.blocks, [&](const PairSums& x) { return angular_correlation_length(x, grid); });
  r.fit = fit_anisotropy(sector_centres(grid), r.xi_theta, r.xi_theta_error, r.xi, grid.sector_width());
  r.magnitude = magnitude_length(s.blocks, grid, settings.magnitude);
  // Eq. 5.3's shape for the decay length per direction: ξ_|C|(θ) = ξ̄ (1 − a0 sin 2(θ − θ0)),
  // ξ̄ the mean over the sectors; no fit unless every sector is finite.
  const std::vector<double>& abs_theta = r.magnitude.xi_theta;
  if (std::all_of(abs_theta.begin(), abs_theta.end(), [](double x) { return std::isfinite(x); }))
    r.fit_abs =
        fit_anisotropy_about_mean(sector_centres(grid), abs_theta, r.magnitude.xi_theta_error, grid.sector_width());
  r.direction = direction_length(s.blocks, grid);
  r.map = correlation_map(s.map, total.norm, grid);
  r.normal = force_distribution(s.normal, settings.force_bin_width, settings.force_max);
  r.binary = force_distribution(s.binary, settings.force_bin_width, settings.force_max);
  r.peak = decide_peak(s.normal, settings.kde_bandwidth, settings.force_max, settings.bootstrap, seed);
  return r;
}

Clusters clusters_of(const Run& run, int window, long long frame) {
  Clusters c;
  c.last_frame = run.reader.frame_index(frame);
  c.first_frame = c.last_frame + 1 - std::size_t(window);
  std::vector<std::array<std::int32_t, 2>> pairs;
  io::Frame last;
  for (std::size_t k = c.first_frame; k <= c.last_frame; ++k) {
    io::Frame f = run.reader.frame(k);
    pairs.insert(pairs.end(), f.contacts.pair.begin(), f.contacts.pair.end());
    if (k == c.first_frame) c.first_step = f.step;
    if (k == c.last_frame) last = std::move(f);
  }
  try {
    c.label = contact_clusters(run.grains, pairs);
  } catch (const UsageError& e) {
    throw UsageError("'" + run.path + "' frames " + std::to_string(c.first_frame) + "-" + std::to_string(c.last_frame) +
                     ": " + e.what());
  }
  c.last_step = last.step;
  c.position = last.position;
  c.box = last.box;
  c.count = c.label.empty() ? 0 : *std::max_element(c.label.begin(), c.label.end());
  return c;
}

}  // namespace

DirectionLength direction_length(const std::vector<PairSums>& blocks, const LagGrid& grid) {
  DirectionLength d;
  d.xi_theta = direction_correlation_length(total_of(blocks, grid), grid);
  d.xi_theta_error = jackknife_errors(blocks, [&](const PairSums& x) { return direction_correlation_length(x, grid); });
  d.fit = fit_anisotropy_about_mean(sector_centres(grid), d.xi_theta, d.xi_theta_error, grid.sector_width());
  return d;
}

// Constants measured with bench/bench_correlation (docs/performance.md, "gf-correlate"):
// seconds per pair visited within ℓ_max by the exact sums, per grid point and log2 of the
// grid size for the three transforms, and per lag within ℓ_max binned from the grid.
// Measured on one core of a loaded machine: 9–13 ns per pair; 0.4–1.4 ns per point and log2
// (the larger grids, beyond the caches, at the top); the estimates are good to a factor 2.
constexpr double kSecondsPerPair = 10e-9;
constexpr double kSecondsPerPointLog = 0.7e-9;
constexpr double kSecondsPerLag = 10e-9;

double pair_sum_seconds(double grains, const Box& box, double max_lag) {
  return kSecondsPerPair * 0.5 * grains * grains * M_PI * max_lag * max_lag / box.area();
}

double fft_seconds(const Box& box, double cell, double max_lag) {
  const FftShape shape = fft_shape(box, cell);
  const double points = shape.points(), lags = points * M_PI * max_lag * max_lag / box.area();
  return kSecondsPerPointLog * 3 * points * std::log2(points) + kSecondsPerLag * lags;
}

Run open_run(const std::string& path, double from_strain, bool detect_transient) {
  Run run{io::RunIdentity{}, io::TrajectoryReader(path)};
  const io::TrajectoryReader& reader = run.reader;
  const io::Parameters p = reader.parameters();
  auto bad = [&](const std::string& what) { return UsageError("'" + path + "': " + what); };
  if (p.has("program") && p.get_string("program") == "gf-pack")
    throw bad("is a packing (made by gf-pack), not a trajectory; shear it with gf-shear first");
  if (!reader.has_contacts()) throw bad("no contacts stored (no /contacts group): not a gf-shear trajectory");
  if (!reader.has_observable("strain")) throw bad("no /observables/strain: not a gf-shear trajectory");
  const Box box = reader.box(0);
  if (!box.periodic_y) throw bad("the box is open in y (an incline run); gf-correlate needs a Lees-Edwards shear run");

  static_cast<io::RunIdentity&>(run) = io::read_run_identity(reader, p, path);
  const std::vector<double> radius = reader.grains().radius;
  run.mean_diameter = 2 * std::accumulate(radius.begin(), radius.end(), 0.0) / double(radius.size());
  run.half_side = 0.5 * std::min(box.lx, box.ly);

  const std::vector<double> observed = reader.observable_scalar("strain");
  if (detect_transient) {
    std::vector<std::vector<double>> series;
    for (const char* name : {"temperature", "pressure"}) {
      if (!reader.has_observable(name))
        throw bad(std::string("no /observables/") + name + " to detect the transient in");
      series.push_back(reader.observable_scalar(name));
      if (series.back().size() != observed.size())
        throw bad(std::string("/observables/") + name + " and /observables/strain differ in length");
    }
    const std::size_t row = mser_first_row(series);
    if (row < observed.size()) from_strain = std::max(from_strain, std::fabs(observed[row]));
  }
  const std::vector<double> strain = frame_strains(reader, observed);
  for (std::size_t k = 0; k < strain.size(); ++k)
    // The tolerance absorbs the round-off of strain = γ̇·t at the frame meant to start at it.
    if (std::fabs(strain[k]) >= from_strain - 1e-9) run.frames.push_back(k);
  if (run.frames.empty())
    throw bad("--from-strain " + format_number(from_strain) + " is past the end of the run (last frame at strain " +
              format_number(std::fabs(strain.back())) + ")");
  run.first_strain = std::fabs(strain[run.frames.front()]);
  run.last_strain = std::fabs(strain[run.frames.back()]);
  return run;
}

Report correlate(const std::vector<std::string>& runs, const std::vector<std::string>& references,
                 const Settings& settings) {
  if (runs.empty()) throw UsageError("no input trajectory");
  if (settings.xi_el && !references.empty()) throw UsageError("give --reference or --xi-el, not both");
  Report report;
  report.settings = settings;
  for (const auto& path : runs) report.runs.push_back(open_run(path, settings.from_strain, settings.detect_transient));
  for (const auto& path : references)
    report.references.push_back(open_run(path, settings.from_strain, settings.detect_transient));

  // One binning for all runs: σ from the first run; ℓ_max within every run's half box.
  const double sigma = report.runs.front().mean_diameter;
  report.mean_diameter = sigma;
  const Run* narrowest = &report.runs.front();
  for (const auto* list : {&report.runs, &report.references})
    for (const Run& r : *list)
      if (r.half_side < narrowest->half_side) narrowest = &r;
  if (settings.whole_box && settings.max_lag > 0) throw UsageError("give --max-lag or --whole-box, not both");
  const double max_lag = settings.whole_box     ? narrowest->half_side
                         : settings.max_lag > 0 ? settings.max_lag
                                                : std::min(15 * sigma, narrowest->half_side);
  if (max_lag > narrowest->half_side)
    throw UsageError("option --max-lag: " + format_number(max_lag) + " exceeds half the shorter box side (" +
                     format_number(narrowest->half_side) + ") of '" + narrowest->path + "'");
  const double bin_width = settings.bin_width > 0 ? settings.bin_width : sigma / 20;
  int coarse = std::max(1, int(std::lround(sigma / 4 / bin_width)));
  if (settings.abs_bin_width > 0) {
    coarse = int(std::lround(settings.abs_bin_width / bin_width));
    if (coarse < 1 || std::fabs(settings.abs_bin_width - coarse * bin_width) > 1e-6 * settings.abs_bin_width)
      throw UsageError("option --abs-bin-width: " + format_number(settings.abs_bin_width) +
                       " is not a whole multiple of the radial bin width " + format_number(bin_width));
  }
  // The default map bin σ/5, or coarser where that would exceed the bound on the map's side
  // (lags beyond 200σ, reached only with --whole-box or a large --max-lag).
  const double map_bin = settings.map_bin > 0                      ? settings.map_bin
                         : 2 * max_lag / (sigma / 5) > kMaxMapSide ? 2 * max_lag / kMaxMapSide
                                                                   : sigma / 5;
  report.grid = LagGrid::make(bin_width, max_lag, settings.angle_bins, map_bin, coarse);
  report.settings.bin_width = report.grid.bin_width;
  report.settings.abs_bin_width = coarse * report.grid.bin_width;
  report.settings.max_lag = report.grid.max_lag();
  report.settings.map_bin = report.grid.map_bin;

  if (settings.clusters_window > 0)
    for (const Run& r : report.runs) {
      const long long frames = (long long)r.reader.frame_count(), k = settings.clusters_frame;
      if (k >= frames || k < -frames)
        throw UsageError("option --clusters-frame " + std::to_string(k) + ": out of range, '" + r.path + "' has " +
                         std::to_string(frames) + " frame(s)");
      if (r.reader.frame_index(k) + 1 < std::size_t(settings.clusters_window))
        throw UsageError("option --clusters-window: '" + r.path + "' has fewer than " +
                         std::to_string(settings.clusters_window) + " frames up to --clusters-frame " +
                         std::to_string(settings.clusters_frame));
    }

  double total_frames = 0, done_frames = 0;
  for (const auto* list : {&report.runs, &report.references})
    for (const Run& r : *list) total_frames += double(r.frames.size());
  Progress bar("gf-correlate", total_frames, settings.quiet);
  std::string status;
  auto done = [&] { bar.update(++done_frames, status); };

  // The method: fixed by the user, or the cheaper one by the cost model on the largest run.
  const double cell = settings.fft_cell > 0 ? settings.fft_cell : sigma / 20;
  report.settings.fft_cell = cell;
  report.method = settings.map_method == MapMethod::fft ? MapMethod::fft : MapMethod::pairs;
  report.method_reason = settings.map_method == MapMethod::automatic ? "" : "chosen by --map-method";
  if (settings.map_method == MapMethod::fft)
    for (const auto* list : {&report.runs, &report.references})
      for (const Run& r : *list) (void)fft_shape(r.reader.box(0), cell);  // refuse a too fine grid before reading
  if (settings.map_method == MapMethod::automatic) {
    const Run* largest = &report.runs.front();
    for (const auto* list : {&report.runs, &report.references})
      for (const Run& r : *list)
        if (r.grains > largest->grains) largest = &r;
    const Box box = largest->reader.box(0);
    // Only grains with a contact enter the sums: count them in the run's last averaged frame
    // (the first may be the contact-free start of a run averaged from strain 0).
    std::size_t loaded = 0;
    try {
      loaded = loaded_grains(largest->reader.frame(largest->frames.back())).position.size();
    } catch (const UsageError& e) {
      throw UsageError("'" + largest->path + "' frame " + std::to_string(largest->frames.back()) + ": " + e.what());
    }
    const double pairs = pair_sum_seconds(double(loaded), box, report.grid.max_lag());
    const std::string which =
        " for the largest run ('" + largest->path + "', " + std::to_string(loaded) + " grains with a contact)";
    // A grid beyond the bound on every run's memory leaves the exact sums.
    bool grid_fits = true;
    for (const auto* list : {&report.runs, &report.references})
      for (const Run& r : *list) try {
          (void)fft_shape(r.reader.box(0), cell);
        } catch (const UsageError&) {
          grid_fits = false;
        }
    if (grid_fits) {
      const double fft = fft_seconds(box, cell, report.grid.max_lag());
      report.method = fft < pairs ? MapMethod::fft : MapMethod::pairs;
      report.method_reason = "auto: estimated " + format_number(pairs) + " s per frame by pairs, " +
                             format_number(fft) + " s by fft," + which;
    } else {
      report.method_reason = "auto: the FFT grid of --fft-cell " + format_number(cell) + " exceeds " +
                             format_number(kMaxFftPoints) + " cells; estimated " + format_number(pairs) +
                             " s per frame by pairs," + which;
    }
  }
  const Correlator correlator(report.grid);
  FftCorrelator fft(report.grid, cell);
  Accumulate accumulate = [&](const LoadedGrains& g, PairSums& s, std::vector<double>& m) {
    correlator.accumulate(g, s, m);
  };
  if (report.method == MapMethod::fft)
    accumulate = [&](const LoadedGrains& g, PairSums& s, std::vector<double>& m) { fft.accumulate(g, s, m); };
  auto record_shape = [&](const Run& run) {
    if (report.method == MapMethod::fft) report.fft_shapes.push_back(fft_shape(run.reader.box(0), cell));
  };

  for (std::size_t i = 0; i < report.runs.size(); ++i) {
    const Run& run = report.runs[i];
    status = "run " + std::to_string(i + 1) + "/" + std::to_string(report.runs.size());
    const RunSums sums = accumulate_run(run, report.grid, accumulate, settings.blocks, true, done);
    report.results.push_back(summarise(sums, report.grid, settings, settings.seed + i));
    record_shape(run);
  }

  std::vector<PairSums> pooled;
  for (std::size_t i = 0; i < report.references.size(); ++i) {
    status = "reference " + std::to_string(i + 1) + "/" + std::to_string(report.references.size());
    const RunSums sums = accumulate_run(report.references[i], report.grid, accumulate, settings.blocks, false, done);
    record_shape(report.references[i]);
    report.reference_xi.push_back(correlation_length(total_of(sums.blocks, report.grid)));
    report.reference_xi_error.push_back(xi_error_of(sums.blocks));
    report.reference_xi_length.push_back(correlation_length(total_of(sums.blocks, report.grid), Density::length));
    report.reference_xi_length_error.push_back(xi_error_of(sums.blocks, Density::length));
    const MagnitudeLength m = magnitude_length(sums.blocks, report.grid, settings.magnitude);
    report.reference_xi_abs.push_back(m.xi);
    report.reference_xi_abs_error.push_back(m.xi_error);
    pooled.insert(pooled.end(), sums.blocks.begin(), sums.blocks.end());
  }
  bar.finish();

  if (settings.xi_el) {
    report.xi_el = *settings.xi_el;
    report.xi_el_error = 0;
  } else if (!pooled.empty()) {
    // All reference frames form one ensemble: ξ of the pooled sums, jackknife over all blocks.
    report.xi_el = correlation_length(total_of(pooled, report.grid));
    report.xi_el_error = xi_error_of(pooled);
    report.xi_length_el = correlation_length(total_of(pooled, report.grid), Density::length);
    report.xi_length_el_error = xi_error_of(pooled, Density::length);
    // ξ_|C| likewise: the pooled blocks, with noise floors from their pooled jackknife.
    const MagnitudeLength m = magnitude_length(pooled, report.grid, settings.magnitude);
    report.xi_abs_el = m.xi;
    report.xi_abs_el_error = m.xi_error;
  }
  std::vector<SweepPoint> points, abs_points;
  for (std::size_t i = 0; i < report.runs.size(); ++i) {
    const Run& run = report.runs[i];
    const RunResult& r = report.results[i];
    const double ratio = r.xi / report.xi_el;
    report.xi_ratio.push_back(ratio);
    report.xi_ratio_error.push_back(std::fabs(ratio) *
                                    std::hypot(r.xi_error / r.xi, report.xi_el_error / report.xi_el));
    points.push_back({run.packing_fraction, run.restitution, run.friction, r.xi, r.xi_error});
    const auto [length_ratio, length_ratio_error] =
        ratio_of(r.xi_length, r.xi_length_error, report.xi_length_el, report.xi_length_el_error);
    report.xi_length_ratio.push_back(length_ratio);
    report.xi_length_ratio_error.push_back(length_ratio_error);
    const MagnitudeLength& m = r.magnitude;
    const double abs_ratio = m.xi / report.xi_abs_el;
    report.xi_abs_ratio.push_back(abs_ratio);
    report.xi_abs_ratio_error.push_back(std::fabs(abs_ratio) *
                                        std::hypot(m.xi_error / m.xi, report.xi_abs_el_error / report.xi_abs_el));
    // Runs whose correlations reach the box stay out of ν_bc (their ξ_|C| measures the cell).
    abs_points.push_back({run.packing_fraction, run.restitution, run.friction, m.measurable ? m.xi : kNaN, m.xi_error});
  }
  if (std::isfinite(report.xi_el))
    report.crossings = binary_collision_crossings(points, report.xi_el, report.xi_el_error, settings.threshold);
  if (std::isfinite(report.xi_abs_el))
    report.crossings_abs =
        binary_collision_crossings(abs_points, report.xi_abs_el, report.xi_abs_el_error, settings.threshold);

  if (settings.clusters_window > 0)
    for (const Run& run : report.runs)
      report.clusters.push_back(clusters_of(run, settings.clusters_window, settings.clusters_frame));
  return report;
}

}  // namespace granflow::correlation
