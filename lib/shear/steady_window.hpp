#pragma once
// The steady window of a gf-shear trajectory, as the analysis programs (gf-kinetic,
// gf-network) read it: the observable rows at |strain| ≥ from_strain (sheared runs) or at
// time ≥ from_time (γ̇ = 0), later where the run's own transient ends with detect_transient
// (MSER on T and p, statistics/steady.hpp's mser_first_row, the rule gf-correlate and
// steady_state.py use), and the stored frames written by the steps of that window.
//
// Every refusal is a UsageError of one line naming the file.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.hpp"
#include "io/trajectory.hpp"

namespace granflow::shear_run {

struct WindowSettings {
  double from_strain = 0.5;  // sheared runs
  double from_time = -1;     // γ̇ = 0 runs; negative: the second half of the run
  bool detect_transient = false;
};

// A trajectory opened and checked, with its strain, time and step rows.
struct Opened {
  io::TrajectoryReader reader;
  io::Parameters parameters{};
  std::vector<double> strain{}, time{};
  std::vector<std::int64_t> step{};
  double rate = 0;
};

// UsageError naming the file: a packing, no /observables/strain (not a gf-shear trajectory),
// a box open in y (an incline run; `program` names the program that needs a gf-shear run),
// no observable row.
Opened open(const std::string& path, const std::string& program);

// An observable's rows, checked: present and as long as /observables/strain.
std::vector<double> observable(const Opened& o, const std::string& path, const char* name);
std::vector<Mat2> tensor(const Opened& o, const std::string& path, const char* name);

struct Window {
  std::size_t first_row = 0;
  std::int64_t previous_step = 0;  // step of the row before the window (0 at the start)
};

// UsageError: the window starts past the last row, or holds fewer than 2 rows.
Window window(const Opened& o, const std::string& path, const WindowSettings& s);

// The stored frames (indices) produced by the steps of the window: step > 0, after the row
// before the window, up to the last row.
std::vector<std::size_t> window_frames(const Opened& o, const Window& w);

}  // namespace granflow::shear_run
