// The programs set OpenMP's wait policy themselves: with more threads than free cores,
// libgomp's default (spin 300000 times at every barrier before sleeping) makes --threads 2
// tens of times slower than one thread. A short spin (GOMP_SPINCOUNT=10000, the value the
// tests run with, tests/CMakeLists.txt) is fast on a busy and on an idle machine. libgomp
// reads its environment before main(), so the programs' own setting is only seen when it
// is made before that; libgomp shows the value it uses with OMP_DISPLAY_ENV=verbose.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "programs/run_tool.hpp"

using namespace granflow::testing;

namespace {

// The GOMP_SPINCOUNT libgomp reports at start-up of `TOOL --version` run with the
// environment changes `env` (an `env` argument list); "" if it reports none.
std::string spin_count_seen(const std::string& tool, const std::string& env, bool& libgomp) {
  ScratchDir dir("wait_policy");
  const std::string cmd = "env -u GOMP_SPINCOUNT -u OMP_WAIT_POLICY OMP_DISPLAY_ENV=verbose " + env + " " +
                          tool_path(tool) + " --version </dev/null >/dev/null 2>" + (dir / "err");
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream in(dir / "err");
  const std::string err{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  libgomp = err.find("OPENMP DISPLAY ENVIRONMENT") != std::string::npos;
  std::smatch m;
  if (std::regex_search(err, m, std::regex("GOMP_SPINCOUNT = '([0-9]+)'"))) return m[1];
  return "";
}

// The programs with threads (gf-pack and gf-correlate load no OpenMP runtime).
const char* const kThreaded[] = {"gf-shear", "gf-incline"};

// Skips the test unless the programs' OpenMP runtime is libgomp (the TSan build uses
// Clang's libomp, which has no GOMP_SPINCOUNT).
#define SKIP_UNLESS_LIBGOMP(tool)                                                       \
  do {                                                                                  \
    bool libgomp = false;                                                               \
    if (spin_count_seen(tool, "", libgomp).empty() || !libgomp)                         \
      GTEST_SKIP() << "the OpenMP runtime is not libgomp (it shows no GOMP_SPINCOUNT)"; \
  } while (0)

}  // namespace

TEST(WaitPolicy, ProgramsSetAShortSpinThemselves) {
  for (const char* tool : kThreaded) {
    SKIP_UNLESS_LIBGOMP(tool);
    bool libgomp = false;
    EXPECT_EQ(spin_count_seen(tool, "", libgomp), "10000") << tool;
  }
}

TEST(WaitPolicy, TheUsersSettingsWin) {
  for (const char* tool : kThreaded) {
    SKIP_UNLESS_LIBGOMP(tool);
    bool libgomp = false;
    EXPECT_EQ(spin_count_seen(tool, "GOMP_SPINCOUNT=5", libgomp), "5") << tool;
    // With OMP_WAIT_POLICY the user chose the policy: the programs add nothing, and
    // libgomp derives its spin count from the policy (not 10000).
    EXPECT_NE(spin_count_seen(tool, "OMP_WAIT_POLICY=passive", libgomp), "10000") << tool;
    EXPECT_NE(spin_count_seen(tool, "OMP_WAIT_POLICY=active", libgomp), "10000") << tool;
  }
}

// The program that ran itself again got the same arguments (spaces and quotes included),
// standard input and working directory: its output has the same bytes as a run that
// needed no second start.
TEST(WaitPolicy, TheSecondStartKeepsArgumentsAndInput) {
  SKIP_UNLESS_LIBGOMP("gf-shear");
  ScratchDir dir("wait_policy_args");
  const std::string pack = packed_once("wait_policy_pack", "--grains 60 --packing-fraction 0.7 --seed 3");
  const std::string args = " -i '" + pack + "' --steps 50 --rate 0.01 --quiet -o \"it's here.h5\"";
  for (const char* sub : {"a", "b"}) std::filesystem::create_directories(dir.path / sub);
  const std::string a = "cd '" + (dir / "a") + "' && env -u GOMP_SPINCOUNT -u OMP_WAIT_POLICY " +
                        tool_path("gf-shear") + args + " </dev/null";
  const std::string b =
      "cd '" + (dir / "b") + "' && env GOMP_SPINCOUNT=10000 " + tool_path("gf-shear") + args + " </dev/null";
  ASSERT_EQ(std::system(a.c_str()), 0) << a;
  ASSERT_EQ(std::system(b.c_str()), 0) << b;
  std::ifstream fa(dir / "a/it's here.h5", std::ios::binary), fb(dir / "b/it's here.h5", std::ios::binary);
  const std::string x{std::istreambuf_iterator<char>(fa), std::istreambuf_iterator<char>()};
  const std::string y{std::istreambuf_iterator<char>(fb), std::istreambuf_iterator<char>()};
  ASSERT_FALSE(x.empty());
  EXPECT_TRUE(x == y) << "the outputs differ";
}
