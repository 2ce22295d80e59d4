// "Same options and seed ⇒ identical file contents": every program, run twice with the
// same command line (relative paths, in two directories), writes the same bytes. Nothing
// that depends on the invocation (wall time, speed, the working directory) may enter an
// output file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "programs/run_tool.hpp"

using namespace granflow::testing;

namespace {

// Runs `name args` with `dir` as its working directory; the exit code (stderr to dir/log).
int run_in(const ScratchDir& dir, const std::string& name, const std::string& args) {
  const std::string cmd =
      "cd '" + dir.path.string() + "' && exec " + tool_path(name) + " " + args + " </dev/null >/dev/null 2>>log";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<char> bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The first differing byte of two files, or -1 when they are identical.
long first_difference(const std::string& a, const std::string& b) {
  const std::vector<char> x = bytes_of(a), y = bytes_of(b);
  const std::size_t n = std::min(x.size(), y.size());
  for (std::size_t k = 0; k < n; ++k)
    if (x[k] != y[k]) return long(k);
  return x.size() == y.size() ? -1 : long(n);
}

// Runs the same commands (relative paths) in two scratch directories and checks that
// every listed file has the same bytes in both.
void expect_same_bytes(const std::string& name, const std::vector<std::pair<std::string, std::string>>& commands,
                       const std::vector<std::string>& files) {
  ScratchDir a(name + "_a"), b(name + "_b");
  for (const auto& [tool, args] : commands) {
    ASSERT_EQ(run_in(a, tool, args), 0) << tool << " " << args << " (see " << (a / "log") << ")";
    ASSERT_EQ(run_in(b, tool, args), 0) << tool << " " << args << " (see " << (b / "log") << ")";
  }
  for (const std::string& f : files) {
    ASSERT_GT(bytes_of(a / f).size(), 0u) << f;
    EXPECT_EQ(first_difference(a / f, b / f), -1) << f << ": the two runs differ from this byte on";
  }
}

}  // namespace

TEST(Determinism, PackShearAndCorrelateTwiceGiveTheSameBytes) {
  expect_same_bytes("determinism_shear",
                    {{"gf-pack", "--grains 150 --packing-fraction 0.78 --seed 2 --quiet -o pack.h5"},
                     {"gf-shear",
                      "-i pack.h5 -o run.h5 --rate 1 --steps 400 --frame-every 20 --restitution 0.5 "
                      "--friction 0.4 --quiet"},
                     {"gf-correlate", "run.h5 -o corr.h5 --from-strain 0.1 --blocks 4 --quiet"},
                     {"gf-kinetic", "run.h5 -o kinetic.h5 --from-strain 0.1 --quiet"}},
                    {"pack.h5", "run.h5", "corr.h5", "kinetic.h5"});
}

TEST(Determinism, ShearWithTwoThreadsTwiceGivesTheSameBytes) {
  expect_same_bytes("determinism_threads",
                    {{"gf-pack", "--grains 200 --packing-fraction 0.75 --seed 5 --quiet -o pack.h5"},
                     {"gf-shear", "-i pack.h5 -o run.h5 --rate 0.01 --steps 200 --friction 0.4 --threads 2 --quiet"}},
                    {"pack.h5", "run.h5"});
}

TEST(Determinism, InclinePackAndRunTwiceGiveTheSameBytes) {
  expect_same_bytes("determinism_incline",
                    {{"gf-pack", "--incline --width 10 --height 5 --seed 3 --quiet -o pack.h5"},
                     {"gf-incline", "-i pack.h5 -o run.h5 --angle 20 --steps 1000 --profile-block 500 --quiet"}},
                    {"pack.h5", "run.h5"});
}
