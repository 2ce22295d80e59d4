// Full disks and file edges (issue 45), with the real programs. A full disk is made by
// write_failure_shim.c (LD_PRELOAD: the files whose path contains a pattern get a fixed amount
// of space, then ENOSPC), which runs anywhere, as CI does; FullDiskTmpfs does the same on a real
// tmpfs where the test may mount one, and is skipped elsewhere.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "programs/run_tool.hpp"
#include "unit/expect_frame.hpp"

using namespace granflow::testing;
namespace fs = std::filesystem;

namespace {

// run_tool's prefix that gives the files whose path contains `pattern` `bytes` of space.
std::string full_disk(const std::string& pattern, long long bytes) {
  return "GRANFLOW_FULL_DISK_PATH='" + pattern + "' GRANFLOW_FULL_DISK_AFTER=" + std::to_string(bytes) +
         " LD_PRELOAD='" + std::string(GRANFLOW_FULL_DISK_SHIM) + "'";
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Lines of stderr other than warnings (gf-incline warns of a missing steady state first).
int error_lines(const std::string& err) {
  int n = 0;
  std::istringstream in(err);
  for (std::string line; std::getline(in, line);) n += line.find(": warning: ") == std::string::npos;
  return n;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += n + " ";
  return s;
}

const std::string& shear_packing() {
  return packed_once("full_disk_pack", "--grains 100 --packing-fraction 0.8 --seed 3");
}
const std::string& incline_packing() {
  return packed_once("full_disk_incline", "--incline --width 10 --height 5 --seed 3");
}

const std::string kRun = " --steps 6000 --frame-every 100 --quiet";

// The uninterrupted run the resumed ones must equal.
const std::string& reference_run() {
  static ScratchDir dir("full_disk_reference");
  static const std::string path = dir / "ref.h5";
  static const int code = run_tool("gf-shear", "-i " + shear_packing() + " -o " + path + kRun).exit_code;
  EXPECT_EQ(code, 0);
  return path;
}

// A resumed run against the reference: every frame and observable read back, and h5diff
// on the groups that hold the trajectory (the files' bytes differ: see gf-shear.md).
void expect_same_datasets(const std::string& run) {
  granflow::test_support::expect_same_run(reference_run(), run,
                                          {"pressure", "shear_stress", "temperature", "solver_iterations"});
  if (std::system("command -v h5diff >/dev/null 2>&1") != 0) return;
  for (const char* group : {"/particles", "/observables", "/contacts", "/lees_edwards", "/run"})
    EXPECT_EQ(std::system(("h5diff -q " + reference_run() + " " + run + " " + group + " " + group).c_str()), 0)
        << group;
}

// A fresh gf-shear run in dir/disk that meets a full disk after `bytes`: exit 1, one line
// naming the file system and --resume, its checkpoint and partial output kept.
std::string run_into_full_disk(const ScratchDir& dir, long long bytes) {
  fs::create_directories(dir / "disk");
  const std::string args = "-i " + shear_packing() + " -o " + (dir / "disk/r.h5") + kRun + " --checkpoint-every 0.1";
  const ToolResult r = run_tool("gf-shear", args, full_disk(dir / "disk/", bytes));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("file system holding"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("run the same command with --resume"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir / "disk/.r.h5.checkpoint")) << joined(names_in(dir / "disk"));
  EXPECT_EQ(partials_of(dir / "disk/r.h5").size(), 1u) << joined(names_in(dir / "disk"));
  EXPECT_EQ(names_in(dir / "disk").size(), 2u) << joined(names_in(dir / "disk"));
  return args;
}

TEST(FullDisk, FreshRunKeepsCheckpointAndPartialThenResumesToTheSameRun) {
  ScratchDir dir("full_disk_fresh");
  const std::string args = run_into_full_disk(dir, 3'000'000);
  const ToolResult resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(names_in(dir / "disk"), std::vector<std::string>{"r.h5"});
  expect_same_datasets(dir / "disk/r.h5");
}

TEST(FullDisk, ResumeOnAFullDiskRemovesNothingOfItsStart) {
  ScratchDir dir("full_disk_resume");
  const std::string args = run_into_full_disk(dir, 3'000'000);
  const FileSnapshot checkpoint = snapshot({dir / "disk/.r.h5.checkpoint"});
  // No room at all, then some: the resume fails in its first checkpoint, or in a later one.
  for (long long bytes : {0LL, 2'500'000LL}) {
    SCOPED_TRACE(bytes);
    const ToolResult r = run_tool("gf-shear", args + " --resume", full_disk(dir / "disk/", bytes));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("run the same command with --resume"), std::string::npos) << r.err;
    const std::vector<std::string> left = names_in(dir / "disk");
    EXPECT_EQ(left.size(), 2u) << joined(left);  // no .checkpoint.new
    EXPECT_TRUE(fs::exists(dir / "disk/.r.h5.checkpoint")) << joined(left);
    EXPECT_EQ(partials_of(dir / "disk/r.h5").size(), 1u) << joined(left);
    // The checkpoint is the one it started from, or a later complete one.
    if (bytes == 0) {
      EXPECT_TRUE(snapshot({dir / "disk/.r.h5.checkpoint"}) == checkpoint);
    }
  }
  const ToolResult resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(names_in(dir / "disk"), std::vector<std::string>{"r.h5"});
  expect_same_datasets(dir / "disk/r.h5");
}

// Every program that writes HDF5, its output failing in its last writes (the close): exit 1,
// one line naming the file, no temporary or checkpoint left, the earlier output untouched.
struct Writer {
  const char* name;
  const char* tool;
  std::string args;  // {out}: the output
};

const std::string& analysis_run(const std::string& name, const std::string& options) {
  static std::map<std::string, std::pair<std::unique_ptr<ScratchDir>, std::string>> made;
  auto it = made.find(name);
  if (it == made.end()) {
    auto dir = std::make_unique<ScratchDir>("full_disk_" + name);
    const std::string path = *dir / (name + ".h5");
    EXPECT_EQ(run_tool("gf-shear",
                       "-i " + shear_packing() + " -o " + path + " --steps 400 --frame-every 40 --quiet " + options)
                  .exit_code,
              0);
    it = made.emplace(name, std::make_pair(std::move(dir), path)).first;
  }
  return it->second.second;
}

std::vector<Writer> writers() {
  const std::string run = analysis_run("run", "");
  const std::string e0 = analysis_run("e0", "--restitution 0"), fast = analysis_run("fast", "--restitution 0 --rate 2"),
                    slow = analysis_run("slow", "--restitution 0 --rate 0.5");
  return {
      {"gf_pack", "gf-pack", "--grains 100 --quiet -o {out}"},
      {"gf_shear", "gf-shear", "-i " + shear_packing() + " --steps 200 --checkpoint-every 0 --quiet -o {out}"},
      {"gf_incline", "gf-incline",
       "-i " + incline_packing() + " --steps 200 --angle 20 --profile-block 100 --frame-every 100 --quiet -o {out}"},
      {"gf_correlate", "gf-correlate", run + " --max-lag 5 --from-strain 0.1 --quiet -o {out}"},
      {"gf_network", "gf-network", run + " --from-strain 0.1 --quiet -o {out}"},
      {"gf_kinetic", "gf-kinetic", run + " --from-strain 0.1 --quiet -o {out}"},
      {"gf_stz_d2min", "gf-stz", "d2min -i " + run + " --frames 0 -1 -q -o {out}"},
      {"gf_stz_fit", "gf-stz",
       "fit " + e0 + " " + fast + " " + slow + " --min-packing-fraction 0.7 --from-strain 0.1 -q -o {out}"},
  };
}

std::string with_output(std::string args, const std::string& out) {
  args.replace(args.find("{out}"), 5, out);
  return args;
}

TEST(FullDisk, EveryWriterFailingAtCloseExitsOneAndLeavesTheOldOutput) {
  for (const Writer& w : writers()) {
    SCOPED_TRACE(w.name);
    ScratchDir dir(std::string("full_disk_close_") + w.name);
    const std::string out = dir / "out.h5";
    const ToolResult first = run_tool(w.tool, with_output(w.args, out));
    ASSERT_EQ(first.exit_code, 0) << first.err;
    const auto size = (long long)fs::file_size(out);
    const FileSnapshot before = snapshot({dir.path.string()});
    // Room for all but the last byte: the output fails in its last writes, when it is closed.
    const ToolResult r = run_tool(w.tool, with_output(w.args, out), full_disk(dir / ".out.h5.part-", size - 1));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(error_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("out.h5"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
    EXPECT_TRUE(snapshot({dir.path.string()}) == before) << joined(names_in(dir.path));
  }
}

TEST(FullDisk, GfXdmfNamesTheFileAndTheReason) {
  ScratchDir dir("full_disk_xdmf");
  const std::string out = dir / "out.xdmf2";
  ASSERT_EQ(run_tool("gf-xdmf", "-i " + analysis_run("run", "") + " -o " + out + " -q").exit_code, 0);
  const FileSnapshot before = snapshot({dir.path.string()});
  const ToolResult r = run_tool("gf-xdmf", "-i " + analysis_run("run", "") + " -o " + out + " -q",
                                full_disk(dir / ".out.xdmf2.part-", 0));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("'" + out + "'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(snapshot({dir.path.string()}) == before) << joined(names_in(dir.path));
}

// A real tmpfs, where the test may mount one (root, or a user namespace allowing it).
struct Tmpfs {
  fs::path dir;
  bool mounted = false;
  Tmpfs(const fs::path& at, const std::string& size) : dir(at) {
    fs::create_directories(dir);
    mounted =
        std::system(("mount -t tmpfs -o size=" + size + " tmpfs '" + dir.string() + "' 2>/dev/null").c_str()) == 0;
  }
  bool resize(const std::string& size) const {
    return std::system(("mount -o remount,size=" + size + " '" + dir.string() + "' 2>/dev/null").c_str()) == 0;
  }
  ~Tmpfs() {
    if (mounted && std::system(("umount '" + dir.string() + "'").c_str()) != 0) ADD_FAILURE() << "umount " << dir;
  }
};

TEST(FullDiskTmpfs, PackOnAFullTmpfsAndARunThatResumesOnceSpaceIsFreed) {
  ScratchDir dir("full_disk_tmpfs");
  Tmpfs small(dir.path / "fs", "2m");
  if (!small.mounted)
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root or CAP_SYS_ADMIN); the shim tests cover it";
  {
    // Filled to 8 KiB free, as in the issue.
    std::ofstream filler(small.dir / "filler", std::ios::binary);
    filler << std::string(2 * 1024 * 1024 - 8 * 1024, 'x');
  }
  const ToolResult pack = run_tool("gf-pack", "--grains 300 --quiet -o " + (small.dir / "p.h5").string());
  EXPECT_EQ(pack.exit_code, 1) << pack.err;
  EXPECT_EQ(count_lines(pack.err), 1) << pack.err;
  EXPECT_EQ(names_in(small.dir), std::vector<std::string>{"filler"});
  fs::remove(small.dir / "filler");

  // A run on 3 MB: it fills the file system, keeps its state, and continues once it has room.
  ASSERT_TRUE(small.resize("3m"));
  const std::string args =
      "-i " + shear_packing() + " -o " + (small.dir / "r.h5").string() + kRun + " --checkpoint-every 0.1";
  const ToolResult full = run_tool("gf-shear", args);
  ASSERT_EQ(full.exit_code, 1) << full.err;
  EXPECT_EQ(count_lines(full.err), 1) << full.err;
  EXPECT_NE(full.err.find("run the same command with --resume"), std::string::npos) << full.err;
  EXPECT_EQ(names_in(small.dir).size(), 2u) << joined(names_in(small.dir));
  ASSERT_TRUE(small.resize("64m"));
  const ToolResult resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(names_in(small.dir), std::vector<std::string>{"r.h5"});
  expect_same_datasets((small.dir / "r.h5").string());
}

// ---- file edges ----

TEST(FileEdges, OutputNameOf255Bytes) {
  ScratchDir dir("long_name");
  const std::string name(255, 'n');
  const ToolResult pack = run_tool("gf-pack", "--grains 100 --quiet -o " + (dir / name));
  ASSERT_EQ(pack.exit_code, 0) << pack.err;
  EXPECT_EQ(names_in(dir.path), std::vector<std::string>{name});

  // gf-shear's temporary and checkpoint too: interrupted, then resumed.
  const std::string shear(255, 's');
  const std::string args =
      "-i " + shear_packing() + " -o " + (dir / shear) + " --steps 20000 --frame-every 1000 --quiet";
  const pid_t pid =
      start_tool("gf-shear", args, dir.path.parent_path() / ("long_name_log_" + std::to_string(::getpid())));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(pid, SIGINT);
  const int code = wait_exit_code(pid);
  fs::remove(dir.path.parent_path() / ("long_name_log_" + std::to_string(::getpid())));
  if (code == 0) GTEST_SKIP() << "the run finished before it could be interrupted";
  ASSERT_EQ(code, 1);
  EXPECT_EQ(names_in(dir.path).size(), 3u) << joined(names_in(dir.path));  // packing, checkpoint, partial
  for (const std::string& n : names_in(dir.path)) EXPECT_LE(n.size(), 255u);
  const ToolResult resumed = run_tool("gf-shear", args + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(names_in(dir.path), (std::vector<std::string>{name, shear}));
}

TEST(FileEdges, FifoInputIsRefusedAtOnce) {
  ScratchDir dir("fifo_input");
  const std::string fifo = dir / "in.h5";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const std::string out = " -o " + (dir / "out.h5");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"gf-pack", "--input " + fifo + out},
      {"gf-shear", "-i " + fifo + out},
      {"gf-incline", "-i " + fifo + " --angle 20" + out},
      {"gf-correlate", fifo + out},
      {"gf-network", fifo + out},
      {"gf-kinetic", fifo + out},
      {"gf-stz", "d2min -i " + fifo + " --frames 0 1" + out},
      {"gf-stz", "fit " + fifo + " --min-packing-fraction 0.7" + out},
      {"gf-xdmf", "-i " + fifo + out},
  };
  for (const auto& [tool, args] : cases) {
    SCOPED_TRACE(tool + " " + args);
    const ToolResult r = run_tool(tool, args, "timeout -s KILL 10");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("'" + fifo + "': is a FIFO"), std::string::npos) << r.err;
    EXPECT_EQ(names_in(dir.path), std::vector<std::string>{"in.h5"});
  }
}

TEST(FileEdges, EmptyOutputNameNamesTheOption) {
  ScratchDir dir("empty_output");
  const std::string run = analysis_run("run", "");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"gf-pack", "--grains 100"},
      {"gf-shear", "-i " + shear_packing()},
      {"gf-incline", "-i " + incline_packing() + " --angle 20"},
      {"gf-correlate", run},
      {"gf-network", run},
      {"gf-kinetic", run},
      {"gf-stz", "d2min -i " + run + " --frames 0 1"},
      {"gf-xdmf", "-i " + run},
  };
  for (const auto& [tool, args] : cases) {
    SCOPED_TRACE(tool);
    const ToolResult r = run_tool(tool, args + " -q -o ''");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--output"), std::string::npos) << r.err;
  }
}

TEST(FileEdges, AFileBeingWrittenIsReportedAsAnUnfinishedRun) {
  ScratchDir dir("being_written");
  const std::string out = dir / "r.h5";
  const pid_t pid = start_tool("gf-shear", "-i " + shear_packing() + " -o " + out + " --steps 200000 --quiet",
                               dir.path.parent_path() / ("being_written_log_" + std::to_string(::getpid())));
  ASSERT_TRUE(wait_for_partial(out, pid));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::string partial = partials_of(out).at(0).string();
  const ToolResult r = run_tool("gf-correlate", partial + " -o " + (dir / "c.h5") + " --quiet");
  ::kill(pid, SIGKILL);
  wait_exit_code(pid);
  fs::remove(dir.path.parent_path() / ("being_written_log_" + std::to_string(::getpid())));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("'" + partial + "': is an unfinished run"), std::string::npos) << r.err;
}

}  // namespace
