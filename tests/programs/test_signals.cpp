// Every program, interrupted by SIGINT or SIGTERM in the middle of a job that lasts seconds,
// exits with status 1 saying so on stderr and leaves no output and no temporary; gf-shear and
// gf-incline keep their checkpoint and partial output, as documented, and no final file.
// The signal is sent once the program's temporary .NAME.part-PID exists (the program has
// created its output, so its handlers are installed and its work has begun).
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <tuple>

#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

// The inputs of the long jobs, made once: a packing of 300 grains, an incline start, a
// trajectory of 200 grains with a frame at every one of its 600 steps (seconds of work for
// every analysis), and the same file followed by 128 MiB of unused space (a hole: HDF5 reads
// it as before, and gf-stz fit, which reads only observables, takes seconds to hash it).
struct Inputs {
  ScratchDir dir{"signals_inputs"};
  std::string pack = dir / "pack.h5", incline = dir / "incline.h5", run = dir / "run.h5", big = dir / "big.h5";
  Inputs() {
    EXPECT_EQ(run_tool("gf-pack", "--grains 300 --packing-fraction 0.78 --seed 2 --quiet -o " + pack).exit_code, 0);
    EXPECT_EQ(run_tool("gf-pack", "--incline --width 20 --height 10 --seed 2 --quiet -o " + incline).exit_code, 0);
    const std::string small = dir / "small.h5";
    EXPECT_EQ(run_tool("gf-pack", "--grains 200 --packing-fraction 0.78 --seed 2 --quiet -o " + small).exit_code, 0);
    EXPECT_EQ(run_tool("gf-shear", "-i " + small + " -o " + run +
                                       " --restitution 0.5 --strain-step 1e-3 --steps 600 --frame-every 1 --quiet")
                  .exit_code,
              0);
    std::filesystem::copy_file(run, big);
    std::filesystem::resize_file(big, std::filesystem::file_size(big) + (std::uintmax_t(128) << 20));
  }
};

const Inputs& inputs() {
  static Inputs i;
  return i;
}

struct Job {
  const char* name;
  const char* program;
  const char* args;  // {pack}, {incline}, {run}, {out}
  bool resumable;    // gf-shear, gf-incline: checkpoint and partial output kept
};

const Job kJobs[] = {
    {"gf_pack", "gf-pack", "--grains 40000 --packing-fraction 0.8 --seed 5 --quiet -o {out}", false},
    {"gf_shear", "gf-shear", "-i {pack} -o {out} --steps 1000000 --frame-every 1000 --quiet", true},
    {"gf_incline", "gf-incline", "-i {incline} -o {out} --angle 20 --steps 1000000 --quiet", true},
    {"gf_correlate", "gf-correlate", "{run} -o {out} --from-strain 0 --quiet", false},
    {"gf_kinetic", "gf-kinetic", "{run} -o {out} --from-strain 0 --quiet", false},
    {"gf_network", "gf-network", "{run} -o {out} --from-strain 0 --quiet", false},
    {"gf_stz_d2min", "gf-stz", "d2min -i {run} --frames 0 -1 -o {out} --quiet", false},
    {"gf_stz_fit", "gf-stz",
     "fit {big} -o {out} --min-packing-fraction 0 --fit-restitution 0.5 --from-strain 0 --quiet", false},
    {"gf_xdmf", "gf-xdmf", "-i {run} -o {out} --quiet", false},
};

std::string substitute(std::string args, const std::string& out) {
  const Inputs& in = inputs();
  for (const auto& [key, value] : {std::pair<std::string, std::string>{"{pack}", in.pack},
                                   {"{incline}", in.incline},
                                   {"{run}", in.run},
                                   {"{big}", in.big},
                                   {"{out}", out}})
    for (auto at = args.find(key); at != std::string::npos; at = args.find(key, at + value.size()))
      args.replace(at, key.size(), value);
  return args;
}

class Interrupted : public ::testing::TestWithParam<std::tuple<std::size_t, int>> {};

TEST_P(Interrupted, ExitsOneLeavingNoOutput) {
  const Job& job = kJobs[std::get<0>(GetParam())];
  const int signal = std::get<1>(GetParam());
  ScratchDir dir(std::string("signal_") + job.name);
  const std::filesystem::path out = dir / "out.h5";
  const std::string log = dir / "log";
  const std::string args = substitute(job.args, out.string());
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = start_tool(job.program, args, log);
  ASSERT_TRUE(wait_for_partial(out, pid)) << job.name << " ended before its temporary appeared";
  ASSERT_EQ(::kill(pid, signal), 0);
  const int code = wait_exit_code(pid);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ifstream in(log);
  const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::filesystem::remove(log);
  EXPECT_EQ(code, 1) << err;
  EXPECT_EQ(count_lines(err), 1) << err;
  // gf-shear and gf-incline: "interrupted at step K of N; checkpoint written: ...".
  EXPECT_NE(err.find(job.resumable ? ": interrupted at step" : ": interrupted by signal"), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(out)) << "a final output after an interruption";
  if (job.resumable) {
    EXPECT_EQ(partials_of(out).size(), 1u) << "the partial output is kept for --resume";
    EXPECT_TRUE(std::filesystem::exists(checkpoint_of(out))) << "the checkpoint is kept for --resume";
    EXPECT_EQ(dir.entries(), 2);
  } else {
    EXPECT_EQ(dir.entries(), 0) << "a temporary left behind";
  }
  EXPECT_LT(seconds, 30) << "the program ran on after the signal";
}

std::string job_name(const ::testing::TestParamInfo<std::tuple<std::size_t, int>>& info) {
  return std::string(kJobs[std::get<0>(info.param)].name) +
         (std::get<1>(info.param) == SIGINT ? "_SIGINT" : "_SIGTERM");
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Signals, Interrupted,
                         ::testing::Combine(::testing::Range<std::size_t>(0, sizeof kJobs / sizeof kJobs[0]),
                                            ::testing::Values(SIGINT, SIGTERM)),
                         job_name);
