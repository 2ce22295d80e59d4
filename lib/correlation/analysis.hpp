#pragma once
// gf-correlate's analysis of shear trajectories (thesis ch. 5): for every run, averages
// over the stored frames past the transient of the force correlation C(ℓ) (isotropic
// and the vector map), ξ and ξ(θ) with the fit of eq. 5.3, and the distributions of
// normal and binary-collision forces; the decay length ξ_|C| of |C̄| with its per-direction
// ξ_|C|(θ) and the box-spanning flag (decay_length.hpp); across runs, ξ/ξ_el and ν_bc(e),
// both for eq. 5.2's signed ξ and for ξ_|C|; optionally the contact clusters of a window of
// frames (Fig. 5.1).
//
// Frames of a run past --from-strain are split into B consecutive blocks of (nearly)
// equal length; every error is a jackknife over these blocks (a bootstrap for the peak
// decision), so blocks must be longer than the flow's correlation time.
// Averages over frames are ratios of sums: C = Σ_frames(pair sums)/Σ_frames W, so a
// frame weighs in with its force content and frames without contacts add nothing.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "correlation/anisotropy_fit.hpp"
#include "correlation/decay_length.hpp"
#include "correlation/fft_correlation.hpp"
#include "correlation/force_correlation.hpp"
#include "correlation/force_distribution.hpp"
#include "correlation/sweep.hpp"
#include "io/run_identity.hpp"
#include "io/trajectory.hpp"

namespace granflow::correlation {

// How the pair sums are computed: exactly over pairs (the reference), by FFT of the gridded
// forces (fft_correlation.hpp), or whichever the cost model below expects to be faster.
enum class MapMethod { pairs, fft, automatic };

struct Settings {
  double from_strain = 0.5;
  // Start each run's average where its own transient ends, if that is later than from_strain:
  // MSER on the block means of its T and p (statistics/steady.hpp, mser_first_row()).
  bool detect_transient = false;
  double bin_width = 0;    // 0: σ/20, σ the mean grain diameter of the first run
  double max_lag = 0;      // 0: min(15σ, half the shortest box side of all runs)
  bool whole_box = false;  // max_lag = half the shortest box side of all runs
  MapMethod map_method = MapMethod::pairs;
  double fft_cell = 0;  // side of the FFT grid's cells; 0: σ/20 (the default bin width)
  int angle_bins = 24;
  double map_bin = 0;        // 0: σ/5
  double abs_bin_width = 0;  // coarse bins of ξ_|C|; 0: the multiple of bin_width nearest to σ/4
  MagnitudeSettings magnitude;
  int blocks = 20;
  double threshold = 1.25;
  std::optional<double> xi_el;  // given instead of reference runs
  double force_bin_width = 0.05;
  double force_max = 10;
  double kde_bandwidth = 0.1;
  int bootstrap = 200;
  std::uint64_t seed = 1;
  int clusters_window = 0;  // frames; 0: no clusters
  long long clusters_frame = -1;
  bool quiet = false;
};

// ξ_dir(θ), eq. 5.2 per direction (force_correlation.hpp), with jackknife errors over the
// blocks, and eq. 5.3's shape fitted about its mean over the finite sectors
// (fit_anisotropy_about_mean).
struct DirectionLength {
  std::vector<double> xi_theta, xi_theta_error;  // [angle_bins]
  AnisotropyFit fit;
};
DirectionLength direction_length(const std::vector<PairSums>& blocks, const LagGrid& grid);

// A trajectory opened and checked, with its identity (io::read_run_identity: path, N, ν, e,
// μ, e_t, γ̇, dt, box) and the frames to average.
struct Run : io::RunIdentity {
  io::TrajectoryReader reader;
  std::vector<std::size_t> frames{};         // past the transient
  double first_strain = 0, last_strain = 0;  // of those frames
  double mean_diameter = 0;
  double half_side = 0;  // min(Lx, Ly)/2
};

// UsageError naming the file: not a trajectory, a packing, no contacts stored, no
// strain, a box not periodic in y, parameters missing, or no frame at strain ≥ from_strain
// (or, with detect_transient, past the run's transient if that ends later).
Run open_run(const std::string& path, double from_strain, bool detect_transient = false);

struct RunResult {
  std::vector<double> c, c_error;    // C̄ per radial bin
  std::vector<double> xi_truncated;  // ξ with integrals up to each bin's upper edge
  double xi = 0, xi_error = 0;
  // ξ with C per unit length (force_correlation.hpp, Density::length), and truncated likewise.
  double xi_length = 0, xi_length_error = 0;
  std::vector<double> xi_length_truncated;
  std::vector<double> xi_theta, xi_theta_error;
  AnisotropyFit fit;
  MagnitudeLength magnitude;  // ξ_|C|, its tail share and flag, ξ_|C|(θ)
  AnisotropyFit fit_abs;      // eq. 5.3's shape fitted to ξ_|C|(θ) (see analysis.cpp)
  DirectionLength direction;  // ξ_dir(θ) and its fit
  std::vector<double> map;    // C on the lag map
  Distribution normal, binary;
  PeakDecision peak;
  std::size_t contacts = 0;
  int blocks = 0;
};

struct Clusters {
  std::vector<std::int32_t> label;  // per grain (see contact_clusters)
  std::vector<Vec2> position;       // at the window's last frame
  Box box;                          // of that frame
  std::size_t first_frame = 0, last_frame = 0;
  std::int64_t first_step = 0, last_step = 0;
  int count = 0;  // clusters
};

struct Report {
  Settings settings;  // with the automatic values resolved
  LagGrid grid;
  double mean_diameter = 0;
  std::vector<Run> runs;
  std::vector<RunResult> results;
  std::vector<Run> references;
  std::vector<double> reference_xi, reference_xi_error;
  double xi_el = AnisotropyFit::kNaN, xi_el_error = AnisotropyFit::kNaN;
  std::vector<double> xi_ratio, xi_ratio_error;  // per run
  std::vector<Crossing> crossings;
  // ξ_length (C per unit length): per reference run, ξ_el of the pooled reference blocks (NaN
  // with --xi-el, which gives ξ_el of the area reading only), and the ratio per run.
  std::vector<double> reference_xi_length, reference_xi_length_error;
  double xi_length_el = AnisotropyFit::kNaN, xi_length_el_error = AnisotropyFit::kNaN;
  std::vector<double> xi_length_ratio, xi_length_ratio_error;
  // The same for ξ_|C|: ξ_el from the pooled reference blocks; crossings over the measurable
  // runs only, one entry per (e, μ) of `crossings`, in the same order.
  std::vector<double> reference_xi_abs, reference_xi_abs_error;
  double xi_abs_el = AnisotropyFit::kNaN, xi_abs_el_error = AnisotropyFit::kNaN;
  std::vector<double> xi_abs_ratio, xi_abs_ratio_error;
  std::vector<Crossing> crossings_abs;
  std::vector<Clusters> clusters;  // per run when settings.clusters_window > 0
  // The method used (pairs or fft, also when settings.map_method is automatic), why, and
  // with fft the grid of each run, then of each reference run.
  MapMethod method = MapMethod::pairs;
  std::string method_reason;
  std::vector<FftShape> fft_shapes;
};

// The pair-sum cost model behind MapMethod::automatic (docs/performance.md): estimated
// seconds per frame of the exact pair sums (pairs within ℓ_max, uniform density) and of
// the FFT path (three transforms of the grid and a pass over its lags within ℓ_max).
double pair_sum_seconds(double grains, const Box& box, double max_lag);
double fft_seconds(const Box& box, double cell, double max_lag);

// The whole analysis, with a progress bar over frames unless settings.quiet.
Report correlate(const std::vector<std::string>& runs, const std::vector<std::string>& references,
                 const Settings& settings);

}  // namespace granflow::correlation
