// Every analysis program refuses a run whose observables hold a non-finite number: NaN, +Inf
// and -Inf planted in one row of each observable dataset a program reads (value, or time
// where the window is found by it), through every program that reads that dataset. Each
// refusal: exit 2, one line naming the file, the dataset and the row, nothing written, the
// input unchanged byte for byte. The undamaged runs are accepted (ObservablesControl).
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "io/hdf5_handle.hpp"
#include "programs/run_tool.hpp"

using namespace granflow;
using namespace granflow::testing;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Element `flat` (row-major) of a double dataset, overwritten in place.
void poke(const std::string& path, const std::string& dataset, std::size_t flat, double value) {
  io::File file = io::open_file(path, true);
  io::Dataset d = io::open_dataset(file.get(), dataset);
  std::vector<double> all = io::read_all<double>(d.get());
  ASSERT_LT(flat, all.size()) << dataset;
  all[flat] = value;
  ASSERT_GE(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), 0) << dataset;
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Small real runs, made once: three sheared runs of 100 grains (ν = 0.76, 0.78, 0.80, e = 0,
// 300 steps, a frame every 50; gf-stz fit needs three dense runs) and an elastic gas at rate 0
// (gf-kinetic --equilibrium).
struct Runs {
  ScratchDir dir{"bad_observables_runs"};
  std::vector<std::string> sheared;
  std::string gas = dir / "gas.h5";
  Runs() {
    for (const char* nu : {"0.76", "0.78", "0.80"}) {
      const std::string pack = dir / (std::string("pack_") + nu + ".h5"),
                        run = dir / (std::string("run_") + nu + ".h5");
      EXPECT_EQ(
          run_tool("gf-pack", std::string("--grains 100 --seed 3 --quiet --packing-fraction ") + nu + " -o " + pack)
              .exit_code,
          0);
      EXPECT_EQ(run_tool("gf-shear", "-i " + pack + " -o " + run +
                                         " --restitution 0 --strain-step 2e-3 --steps 300 --frame-every 50 --quiet")
                    .exit_code,
                0);
      sheared.push_back(run);
    }
    const std::string pack = dir / "pack_gas.h5";
    EXPECT_EQ(run_tool("gf-pack", "--grains 100 --packing-fraction 0.3 --seed 3 --quiet -o " + pack).exit_code, 0);
    EXPECT_EQ(run_tool("gf-shear", "-i " + pack + " -o " + gas +
                                       " --rate 0 --restitution 1 --temperature 1 --steps 300 --frame-every 50 --quiet")
                  .exit_code,
              0);
  }
};

const Runs& runs() {
  static Runs r;
  return r;
}

// How each program reads a run F (the damaged file; the other runs R of gf-stz fit follow it),
// writing OUT. --detect-transient makes every program read temperature and pressure too.
std::string command(const std::string& program, const std::string& file, const std::string& out) {
  const Runs& r = runs();
  if (program == "gf-kinetic") return file + " -o " + out + " --from-strain 0 --detect-transient --quiet";
  if (program == "gf-kinetic --equilibrium")
    return r.sheared[0] + " -o " + out + " --equilibrium " + file + " --extrapolate --from-strain 0 --quiet";
  if (program == "gf-network") return file + " -o " + out + " --from-strain 0 --detect-transient --quiet";
  if (program == "gf-correlate") return file + " -o " + out + " --from-strain 0 --detect-transient --quiet";
  if (program == "gf-stz fit")
    return "fit " + file + " " + r.sheared[1] + " " + r.sheared[2] + " -o " + out +
           " --min-packing-fraction 0 --from-strain 0 --detect-transient --quiet";
  ADD_FAILURE() << program;
  return "";
}

std::string executable(const std::string& program) { return program.substr(0, program.find(' ')); }

struct Case {
  const char* program;  // as in command()
  const char* observable;
  const char* column;   // "value" or "time"
  std::size_t per_row;  // 1: a scalar, 4: a 2x2 tensor
};

// What each program reads from a run's observables (lib/shear/steady_window.cpp, lib/kinetic,
// lib/network, lib/stz/fit_table.cpp, lib/correlation/analysis.cpp).
const Case kCases[] = {
    {"gf-kinetic", "strain", "value", 1},
    {"gf-kinetic", "strain", "time", 1},
    {"gf-kinetic", "temperature", "value", 1},
    {"gf-kinetic", "pressure", "value", 1},
    {"gf-kinetic", "shear_stress", "value", 1},
    {"gf-kinetic", "collisions", "value", 1},
    {"gf-kinetic", "dissipated_energy", "value", 1},
    {"gf-kinetic", "collision_velocity_product", "value", 1},
    {"gf-kinetic", "stress_kinetic", "value", 4},
    {"gf-kinetic", "stress_static", "value", 4},
    {"gf-kinetic", "stress_collisional", "value", 4},
    {"gf-kinetic --equilibrium", "strain", "time", 1},
    {"gf-kinetic --equilibrium", "collisions", "value", 1},
    {"gf-kinetic --equilibrium", "pressure", "value", 1},
    {"gf-network", "strain", "value", 1},
    {"gf-network", "strain", "time", 1},
    {"gf-network", "temperature", "value", 1},
    {"gf-network", "pressure", "value", 1},
    {"gf-network", "stress_static", "value", 4},
    {"gf-network", "stress_collisional", "value", 4},
    {"gf-stz fit", "strain", "value", 1},
    {"gf-stz fit", "strain", "time", 1},
    {"gf-stz fit", "temperature", "value", 1},
    {"gf-stz fit", "pressure", "value", 1},
    {"gf-stz fit", "shear_stress", "value", 1},
    {"gf-correlate", "strain", "value", 1},
    {"gf-correlate", "temperature", "value", 1},
    {"gf-correlate", "pressure", "value", 1},
};

class NonFiniteObservable : public ::testing::TestWithParam<std::size_t> {};

TEST_P(NonFiniteObservable, RefusedNamingFileDatasetAndRow) {
  const Case& c = kCases[GetParam()];
  const Runs& r = runs();
  const std::string& source = std::string(c.program) == "gf-kinetic --equilibrium" ? r.gas : r.sheared[0];
  const std::string dataset = std::string("/observables/") + c.observable + "/" + c.column;
  const std::size_t row = 7, element = c.per_row == 4 ? 1 : 0;  // a tensor's [0][1]
  for (const double value : {kNaN, kInf, -kInf}) {
    SCOPED_TRACE(std::string(c.program) + " with " + std::to_string(value) + " in " + dataset);
    ScratchDir dir("bad_observable");
    ScratchDir out("bad_observable_out");
    const std::string file = dir / "run.h5";
    std::filesystem::copy_file(source, file);
    poke(file, dataset, row * c.per_row + element, value);
    const std::string before = bytes_of(file);
    const ToolResult result = run_tool(executable(c.program), command(c.program, file, out / "out.h5"));
    EXPECT_EQ(result.exit_code, 2) << result.err;
    EXPECT_EQ(count_lines(result.err), 1) << result.err;
    EXPECT_NE(result.err.find("'" + file + "': " + dataset + ": row 7"), std::string::npos) << result.err;
    if (c.per_row == 4) {
      EXPECT_NE(result.err.find("element [0][1]"), std::string::npos) << result.err;
    }
    EXPECT_NE(result.err.find("must be finite"), std::string::npos) << result.err;
    EXPECT_EQ(out.entries(), 0) << "output or partial file left behind";
    EXPECT_EQ(bytes_of(file), before) << "the input was changed";
  }
}

std::string case_name(const ::testing::TestParamInfo<std::size_t>& info) {
  const Case& c = kCases[info.param];
  std::string name = std::string(c.program) + "_" + c.observable + "_" + c.column;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return name;
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Observables, NonFiniteObservable,
                         ::testing::Range<std::size_t>(0, sizeof kCases / sizeof kCases[0]), case_name);

// The undamaged runs pass every command above.
TEST(ObservablesControl, UndamagedRunsAreAccepted) {
  const Runs& r = runs();
  ScratchDir out("bad_observables_control");
  for (const char* program : {"gf-kinetic", "gf-kinetic --equilibrium", "gf-network", "gf-correlate", "gf-stz fit"}) {
    const std::string& file = std::string(program) == "gf-kinetic --equilibrium" ? r.gas : r.sheared[0];
    const ToolResult result = run_tool(executable(program), command(program, file, out / "out.h5"));
    EXPECT_EQ(result.exit_code, 0) << program << ": " << result.err;
    std::filesystem::remove(out / "out.h5");
  }
}

// gf-stz fit names a run it cannot fit and says why: a dense run at the fitted restitution
// whose finite shear stress is negative in every row (s/p < 0) is left out by name, in the
// refusal when no friction keeps three fitted runs, as a note otherwise.
TEST(ObservablesControl, StzFitNamesARunItLeavesOut) {
  const Runs& r = runs();
  ScratchDir dir("stz_fit_left_out");
  const std::string file = dir / "negative.h5";
  std::filesystem::copy_file(r.sheared[0], file);
  {
    io::File f = io::open_file(file, true);
    io::Dataset d = io::open_dataset(f.get(), "/observables/shear_stress/value");
    std::vector<double> s = io::read_all<double>(d.get());
    for (double& v : s) v = -std::fabs(v) - 1e-3;
    ASSERT_GE(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()), 0);
  }
  const std::string common = " --min-packing-fraction 0 --from-strain 0 -o " + (dir / "out.h5");
  const ToolResult refused = run_tool("gf-stz", "fit " + file + " " + r.sheared[1] + " " + r.sheared[2] + common);
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_EQ(count_lines(refused.err), 1) << refused.err;
  EXPECT_NE(refused.err.find("fewer points than parameters"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("left out of the fit: '" + file + "' (x = "), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("s/p = -"), std::string::npos) << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.h5"));
}
