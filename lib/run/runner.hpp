#pragma once
// What every Contact Dynamics runner (gf-shear, gf-incline) shares around the time loop
// of run/driver.hpp: the contact-law and solver options, the run options (frames,
// observables, checkpoints, --resume) with one spelling and meaning, the signature a
// resumed run must match, finding the checkpoint to resume from, and handing the
// output over at the end.
#include <cstdint>
#include <optional>
#include <string>

#include "core/cli.hpp"
#include "core/output_file.hpp"
#include "dynamics/engine.hpp"
#include "run/checkpoint.hpp"
#include "run/driver.hpp"

namespace granflow {

// --restitution, --tangential-restitution, --friction, --tolerance, --max-iterations,
// --alert-distance, --threads.
void add_contact_options(CommandLine& cli);
// The values of those options, validated (UsageError naming the option).
Material material_option(const CommandLine& cli);
SolverSettings solver_option(const CommandLine& cli);

// --frame-every, --observe-every (default observe_every), --checkpoint-every, --resume.
void add_run_options(CommandLine& cli, const std::string& observe_every);

// The options that define the run (all but the ones about this session: --resume,
// --checkpoint-every): a resumed run must be given the same.
std::string run_signature(const CommandLine& cli);

// The time loop's plan from the run options (validated): observables, frames,
// checkpoints beside --output, signature, quiet. Its length is set by set_length.
RunPlan run_plan(const CommandLine& cli);
// total_steps, and frame_every when --frame-every was 0 (100 frames per run).
void set_length(RunPlan& plan, std::int64_t total_steps);

// With --resume and a checkpoint beside the output: that checkpoint, after checking it
// was made with the same options and its partial output is there (UsageError
// otherwise). Without a checkpoint a note says the run starts over; nullopt.
std::optional<Checkpoint> resume_point(const CommandLine& cli, const RunPlan& plan, const OutputFile& out);

// The partial trajectory of a checkpointed run, reopened after its last checkpoint.
io::TrajectoryWriter reopen_output(const Checkpoint& checkpoint, const OutputFile& out);

// run_steps for a resumable output: on a signal the partial output and the checkpoint
// are kept (and Interrupted is rethrown); on any other failure the checkpoint goes
// too, and the output's destructor removes the partial file.
RunStats run_resumable(Engine& engine, io::TrajectoryWriter& writer, OutputFile& out, const RunPlan& plan,
                       RunStats stats, const Observer& observe);

// Writes the /run summary, closes and commits the output, removes the checkpoint, and
// reports on stderr (a warning for unconverged steps always, the summary unless quiet).
void finish_run(const CommandLine& cli, io::TrajectoryWriter& writer, OutputFile& out, const Engine& engine,
                const RunStats& stats, const RunPlan& plan);

}  // namespace granflow
