#pragma once
// What every Contact Dynamics runner (gf-shear, gf-incline) shares around the time loop
// of run/driver.hpp: the contact-law and solver options, the run options (frames,
// observables, checkpoints, --resume) with one spelling and meaning, the signature a
// resumed run must match, starting a run or resuming it from its checkpoint, and handing
// the output over at the end.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "core/vec.hpp"
#include "dynamics/engine.hpp"
#include "io/trajectory.hpp"
#include "run/checkpoint.hpp"
#include "run/driver.hpp"

namespace granflow {

// --restitution, --tangential-restitution, --friction, --tolerance, --max-iterations,
// --max-unconverged, --alert-distance, --activation, --threads.
void add_contact_options(CommandLine& cli);
// The values of those options, validated (UsageError naming the option).
Material material_option(const CommandLine& cli);
SolverSettings solver_option(const CommandLine& cli);
// The --activation rule named (predicted-gap, overlap); UsageError naming the option otherwise.
Activation activation_named(const std::string& name);

// --frame-every, --observe-every (default observe_every), --checkpoint-every, --resume.
void add_run_options(CommandLine& cli, const std::string& observe_every);

// The options that define the run (all but the ones about this invocation: --resume,
// --checkpoint-every, --threads, and --max-unconverged, which can stop a run but not change
// its steps): a resumed run must be given the same.
std::string run_signature(const CommandLine& cli);

// The time loop's plan from the run options (validated): observables, frames,
// checkpoints beside --output, signature, quiet. Its length is set by set_length.
RunPlan run_plan(const CommandLine& cli);
// total_steps, and frame_every when --frame-every was 0 (100 frames per run).
void set_length(RunPlan& plan, std::int64_t total_steps);

// With --resume and a checkpoint beside the output: that checkpoint, with partial_path
// set, after checking that it was made with the same options, that its partial output
// is there (found by inode among the output's temporaries) and holds its frames, and
// that the input (when input_path is given) still has the SHA-256 the run recorded
// (UsageError otherwise; nothing is changed). Without a checkpoint a note says the run
// starts over; nullopt.
std::optional<Checkpoint> resume_point(const CommandLine& cli, const RunPlan& plan, const OutputFile& out,
                                       const std::string& input_path = "");

// The partial trajectory of a checkpointed run, reopened after its last checkpoint.
io::TrajectoryWriter reopen_output(const Checkpoint& checkpoint, const OutputFile& out);

// What a program gives start_or_resume: the engine's set-up, the start state, and its own
// parts of a new output and of a resume.
struct RunStart {
  GrainState grains;  // the start state: a packing or a stored frame
  Box box;
  // Contacts of that frame (empty for a packing): the warm start of the first step and
  // the contacts of the run's first frame.
  io::ContactRecords contacts;
  double rate = 0;  // γ̇ of the engine and of the Lees–Edwards images (box periodic in y)
  Vec2 gravity = Vec2::Zero();
  Material material;
  SolverSettings settings;
  double dt = 0;
  std::string input_path;  // recorded in /parameters (io::add_input)
  // Adds the program's own values to /parameters of a new output, after the provenance
  // and the input. Optional.
  std::function<void(io::Parameters&)> add_parameters;
  // On a resume: restores the program's own state from the checkpoint file, where
  // RunPlan::checkpoint_extra wrote it (e.g. gf-incline's profiles). Optional.
  std::function<void(const io::TrajectoryReader& checkpoint)> restore;
};

// An engine and its output, ready for run_resumable.
struct StartedRun {
  Engine engine;
  io::TrajectoryWriter writer;
  RunStats stats;
};

// With --resume and a checkpoint (resume_point): adopts the checkpoint's partial output
// as out's temporary, and returns the engine at the checkpoint's state and step, its
// warm start, the program's state (start.restore), the statistics so far and the
// reopened partial output. Otherwise (starting over): removes any old checkpoint, and
// returns the engine at start.grains with the warm start of start.contacts, and a new
// output at out.temp_path(), marked unfinished, holding /parameters (provenance, input,
// start.add_parameters), the grains, the Lees–Edwards rate (box periodic in y) and the
// first frame (step 0, with start.contacts). Either way the output's stale temporaries
// are removed.
StartedRun start_or_resume(const CommandLine& cli, const RunPlan& plan, OutputFile& out, const RunStart& start);

// run_steps for a resumable output: on a signal the partial output and the checkpoint
// are kept (and Interrupted is rethrown). On a write failure (WriteFailure: a full file
// system, a quota, an I/O error) the partial output is never written again and, when a
// checkpoint exists, both are kept for a --resume once the cause is fixed (WriteFailure
// saying so, naming the file system); without one the partial output is removed. On any
// other failure the checkpoint goes too, and the output's destructor removes the partial
// file.
RunStats run_resumable(Engine& engine, io::TrajectoryWriter& writer, OutputFile& out, const RunPlan& plan,
                       RunStats stats, const Observer& observe);

// Writes the program's last datasets (`last`, optional), the /run summary, closes and
// commits the output, removes the checkpoint, and reports on stderr (a warning for
// unconverged steps always, the summary unless quiet). A write failure keeps the
// checkpoint and the partial output as run_resumable does.
void finish_run(const CommandLine& cli, io::TrajectoryWriter& writer, OutputFile& out, const Engine& engine,
                const RunStats& stats, const RunPlan& plan,
                const std::function<void(io::TrajectoryWriter&)>& last = {});

}  // namespace granflow
