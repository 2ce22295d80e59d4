#pragma once
// Trajectory and packing files: HDF5 in the H5MD 1.1 layout of docs/file-format.md
// (Trajectory files; Names and units). A packing is a trajectory with one frame.
//
//   /h5md                          version [1,1], author, creator
//   /parameters                    one attribute per parameter + provenance
//   /particles/grains/{radius,mass,fixed}                 [N]
//   /particles/grains/{position,velocity}                 H5MD element, value [n][N][2]
//   /particles/grains/{orientation,angular_velocity}      H5MD element, value [n][N]
//   /particles/grains/box          dimension, boundary; edges element [n][2][2]
//   /lees_edwards                  rate; offset element [n] (boxes periodic in y)
//   /contacts/frame_offset [n+1] and the flat contact columns
//   /observables/<name>            H5MD elements, value [rows] or [rows][2][2]
//
// An H5MD element is a group holding step [n] (int64), time [n] (double) and value.
// /contacts exists once a frame carrying contacts has been written; frames written
// without contacts then count zero rows.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "core/contact_records.hpp"
#include "core/error.hpp"
#include "core/vec.hpp"
#include "geometry/box.hpp"

namespace granflow::io {

struct GrainProperties {
  std::vector<double> radius, mass;
  std::vector<std::uint8_t> fixed;  // 1 for immobile base grains (incline)
};

// Contacts of one frame (the engine's type: see core/contact_records.hpp).
using ContactRecords = granflow::ContactRecords;

struct Frame {
  std::int64_t step = 0;
  double time = 0;
  Box box;
  std::vector<Vec2> position, velocity;  // velocity in the lab frame
  std::vector<double> orientation, angular_velocity;
  ContactRecords contacts;
  bool has_contacts = false;
};

// Input parameters and provenance (command_line, program, version, input,
// input_sha256), stored as one attribute each on /parameters, with native types.
class Parameters {
 public:
  using Value = std::variant<double, std::int64_t, std::string>;

  Parameters() = default;
  // Parameters read from a file: errors name the file.
  explicit Parameters(std::string origin) : origin_(std::move(origin)) {}

  void set(const std::string& name, double value) { values_[name] = value; }
  void set(const std::string& name, std::int64_t value) { values_[name] = value; }
  void set(const std::string& name, std::string value) { values_[name] = std::move(value); }
  void set(const std::string& name, const char* value) { values_[name] = std::string(value); }
  // Any other integer (int, unsigned, bool...) is stored as int64.
  template <class T>
  requires std::is_integral_v<T>
  void set(const std::string& name, T value) { values_[name] = std::int64_t(value); }

  bool has(const std::string& name) const { return values_.contains(name); }
  // UsageError naming the parameter (and the file) if absent or of another type;
  // get_double also accepts an integer.
  double get_double(const std::string& name) const;
  std::int64_t get_int(const std::string& name) const;
  const std::string& get_string(const std::string& name) const;
  // In name order.
  const std::map<std::string, Value>& items() const { return values_; }

 private:
  const Value& find(const std::string& name) const;
  [[noreturn]] void wrong_type(const std::string& name, const char* expected) const;

  std::string origin_;
  std::map<std::string, Value> values_;
};

// The unit of every time a trajectory stores (the `time` of each H5MD element), named
// by the H5MD `unit` attribute of each time dataset: kCodeTime, the engine's own time
// (gf-pack, gf-shear), unless a program chooses another, e.g. gf-incline's τ
// (io/units.hpp: "T" and "tau").
inline constexpr const char* kCodeTime = "T";
struct TimeUnit {
  std::string name = kCodeTime;
  double code_per_unit = 1;  // the unit in code time: stored time = code time / this
};

class TrajectoryWriter {
 public:
  // Creates (truncates) path and writes /h5md. Object timestamps are off, so the same
  // calls give byte-identical files. RuntimeFailure naming the path on any HDF5 error.
  explicit TrajectoryWriter(const std::string& path, const std::string& author = "granflow user");
  TrajectoryWriter(TrajectoryWriter&&) noexcept;
  TrajectoryWriter& operator=(TrajectoryWriter&&) noexcept;
  ~TrajectoryWriter();  // closes; never throws (a failure is reported on stderr)

  // Replaces any attribute of the same name.
  void write_parameters(const Parameters& parameters);
  // The same for any group (created if missing), e.g. a run summary in /run.
  void write_attributes(const std::string& group_path, const Parameters& values);
  // Once, before the first frame; N ≥ 1 and all three columns of size N. The box gives
  // the boundary (periodic in y or not); its edges are written with every frame.
  void write_grains(const GrainProperties& grains, const Box& box);
  // Times given to append_frame and append_observable are code times; they are stored
  // in `unit`. On a new file: before write_grains and the first observable (their
  // time datasets are labelled when created). On a reopened one: the unit its time
  // datasets name (UsageError naming the file otherwise), for the times appended.
  void set_time_unit(const TimeUnit& unit);
  // A code time in the file's unit.
  double file_time(double code_time) const;
  // γ̇ of the Lees–Edwards images (boxes periodic in y; 0 until set).
  void set_lees_edwards_rate(double rate);
  // Steps must increase from frame to frame; every per-grain column has size N.
  void append_frame(const Frame& frame);

  // One row of /observables/<name>; steps of one observable must increase. Rows are
  // buffered and written in blocks, so calling this every simulation step is cheap.
  void append_observable(const std::string& name, std::int64_t step, double time, double value);
  void append_observable(const std::string& name, std::int64_t step, double time, const Mat2& value);

  // A fixed-size array of doubles written in one go at an absolute path such as
  // /profiles/velocity_x (missing parent groups are created; the path must be new), with
  // `attributes` (e.g. meaning, units) on the dataset, and, given `units`, its H5MD
  // `unit` (io/units.hpp). shape's product must equal values.size(). For analysis results, e.g. gf-incline's depth profiles.
  void write_array(const std::string& path, const std::vector<std::size_t>& shape, const std::vector<double>& values,
                   const Parameters& attributes = {});

  // Marks the file as an unfinished run (root attribute `unfinished`, see
  // docs/file-format.md), which readers refuse. close() removes the mark;
  // close_unfinished() keeps it (an interrupted run, continued by --resume).
  void mark_unfinished();

  void flush();  // writes buffered rows and flushes the file
  void close();  // flush and close; further calls fail
  void close_unfinished();
  // After a write failure: gives the file up without writing to it again (no flush, no
  // close), so that it stays as its last flush left it, as after a kill -9; further calls
  // fail. The process must end through run_tool (io::abandon_file).
  void abandon();

  std::size_t frame_count() const;
  const std::string& path() const;

  // For checkpoint/resume: reopens a trajectory written by this class, cuts every
  // time-dependent dataset to its first keep_frames frames (contacts to those frames'
  // rows) and every observable to its rows with step <= keep_observables_through_step,
  // then appends from there. UsageError if the file is not a trajectory or has fewer
  // than keep_frames frames.
  static TrajectoryWriter reopen_for_append(const std::string& path, std::size_t keep_frames,
                                            std::int64_t keep_observables_through_step);

 private:
  struct Impl;
  explicit TrajectoryWriter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

class TrajectoryReader {
 public:
  // Checks the file up front; UsageError with one line naming the path and what is
  // wrong (missing, not HDF5 or truncated, missing group, dataset of the wrong shape).
  // Every later error reading it is a UsageError naming the path too.
  // A file marked unfinished (TrajectoryWriter::mark_unfinished) is refused too, unless
  // accept_unfinished (resume only).
  explicit TrajectoryReader(const std::string& path, bool accept_unfinished = false);
  // A resumable run's partial output as of a checkpoint that counted `frames` frames
  // (resume only): unfinished, and its datasets may hold more rows than that, written
  // after the checkpoint by a process killed before the next one (HDF5 flushes the
  // extent of some datasets and not of others in between). Sees only those frames and
  // their contacts; UsageError naming the path if a dataset holds fewer.
  static TrajectoryReader partial_output(const std::string& path, std::size_t frames);
  TrajectoryReader(TrajectoryReader&&) noexcept;
  TrajectoryReader& operator=(TrajectoryReader&&) noexcept;
  ~TrajectoryReader();

  std::size_t frame_count() const;
  std::size_t grain_count() const;
  GrainProperties grains() const;
  Box box(std::size_t frame) const;
  // Reads only frame k, with its contacts when the file has them (has_contacts).
  Frame frame(std::size_t k) const;
  // A --frame option's value as an index: negative counts from the end (−1 = last);
  // UsageError naming the file, the frame count and `option` (how the message names the
  // value: "--frame K is out of range") if out of range.
  std::size_t frame_index(long long k, const std::string& option = "--frame") const;
  std::vector<std::int64_t> frame_steps() const;
  std::vector<double> frame_times() const;
  bool has_contacts() const;

  Parameters parameters() const;  // empty if the file has no /parameters
  // The attributes of a group or dataset; empty if it is absent.
  Parameters attributes(const std::string& group_path) const;
  double lees_edwards_rate() const;  // 0 if absent

  bool has_observable(const std::string& name) const;
  std::vector<std::string> observable_names() const;
  std::vector<std::int64_t> observable_step(const std::string& name) const;
  // Times and values are checked as read: a non-finite one is a UsageError naming the file,
  // the dataset and the row (frame_check.hpp, observable_problem).
  std::vector<double> observable_time(const std::string& name) const;
  std::vector<double> observable_scalar(const std::string& name) const;
  std::vector<Mat2> observable_tensor(const std::string& name) const;

  // An array of doubles (as write_array stores it), flattened row-major; its shape in
  // *shape if given. UsageError naming the file if the dataset is absent.
  std::vector<double> array(const std::string& path, std::vector<std::size_t>* shape = nullptr) const;

  const std::string& path() const;

 private:
  TrajectoryReader(const std::string& path, bool accept_unfinished, std::optional<std::size_t> as_of_frames);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A packing: a one-frame trajectory with its grains and parameters.
void write_packing(const std::string& path, const Frame& frame, const GrainProperties& grains,
                   const Parameters& parameters);

}  // namespace granflow::io
