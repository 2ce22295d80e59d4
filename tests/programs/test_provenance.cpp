// Provenance and command lines of every program, run as a user runs them: /parameters
// records the options as the program used them, each option with one HDF5 type whatever
// was typed; an option that cannot apply to the run is refused instead of ignored; a
// branch of a branch names its parent's physics; --help fits 100 columns.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <variant>

#include "io/trajectory.hpp"
#include "programs/run_tool.hpp"

using namespace granflow::testing;
namespace io = granflow::io;

namespace {
const std::string& biperiodic() { return packed_once("prov_biperiodic", "--grains 40 --packing-fraction 0.5"); }
const std::string& incline() { return packed_once("prov_incline", "--incline --width 8 --height 3 --seed 2"); }

io::Parameters parameters_of(const std::string& path) { return io::TrajectoryReader(path).parameters(); }

bool is_double(const io::Parameters& p, const std::string& name) {
  return p.has(name) && std::holds_alternative<double>(p.items().at(name));
}
bool is_int(const io::Parameters& p, const std::string& name) {
  return p.has(name) && std::holds_alternative<std::int64_t>(p.items().at(name));
}

std::int64_t mobile_grains(const std::string& path) {
  std::int64_t n = 0;
  for (auto f : io::TrajectoryReader(path).grains().fixed) n += f ? 0 : 1;
  return n;
}

// What a program prints on stdout.
std::string stdout_of(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return out;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  ::pclose(pipe);
  return out;
}

// Columns of a line of UTF-8 text, one per code point (continuation bytes do not count).
std::size_t code_points(const std::string& line) {
  std::size_t n = 0;
  for (unsigned char c : line) n += (c & 0xC0) != 0x80;
  return n;
}
}  // namespace

TEST(GfPackProvenance, InclineRecordsTheGrainCountTheHeightGave) {
  ScratchDir dir("prov_pack_incline");
  const std::string out = dir / "incline.h5";
  auto r = run_tool("gf-pack", "--incline --width 10 --height 2 --seed 4 --quiet -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Parameters p = parameters_of(out);
  EXPECT_EQ(p.get_int("grains"), mobile_grains(out));
  EXPECT_NE(p.get_int("grains"), 1000);
  EXPECT_DOUBLE_EQ(p.get_double("height"), 2.0);
  // A biperiodic option does not apply to an incline start and is not recorded.
  EXPECT_FALSE(p.has("packing-fraction"));
  EXPECT_FALSE(p.has("tolerance"));
  EXPECT_FALSE(p.has("frame"));
}

TEST(GfPackProvenance, InclineWithGrainsRecordsNoHeight) {
  ScratchDir dir("prov_pack_incline_grains");
  const std::string out = dir / "incline.h5";
  auto r = run_tool("gf-pack", "--incline --width 10 --grains 30 --quiet -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Parameters p = parameters_of(out);
  EXPECT_EQ(p.get_int("grains"), 30);
  EXPECT_EQ(mobile_grains(out), 30);
  EXPECT_FALSE(p.has("height"));
}

TEST(GfPackProvenance, RepackRecordsTheInputsGrainCount) {
  ScratchDir dir("prov_pack_repack");
  const std::string out = dir / "repacked.h5";
  auto r = run_tool("gf-pack", "-i " + biperiodic() + " --packing-fraction 0.6 --quiet -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Parameters p = parameters_of(out);
  EXPECT_EQ(p.get_int("grains"), 40);
  EXPECT_EQ(p.get_int("frame"), -1);
  // Sizes and seed come from the input, not from options.
  EXPECT_FALSE(p.has("mean-diameter"));
  EXPECT_FALSE(p.has("polydispersity"));
  EXPECT_FALSE(p.has("seed"));
  EXPECT_FALSE(p.has("width"));
}

TEST(ProvenanceTypes, OneTypePerOptionWhateverWasTyped) {
  ScratchDir dir("prov_types");
  for (const char* height : {"2", "2.5"}) {
    const std::string out = dir / (std::string("h") + height + ".h5");
    auto r =
        run_tool("gf-pack", std::string("--incline --width 6 --height ") + height + " --seed 1e0 --quiet -o " + out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const io::Parameters p = parameters_of(out);
    EXPECT_TRUE(is_double(p, "height")) << "--height " << height;
    EXPECT_TRUE(is_double(p, "width")) << "--height " << height;
    EXPECT_TRUE(is_double(p, "mean-diameter"));
    EXPECT_TRUE(is_int(p, "seed"));
    EXPECT_TRUE(is_int(p, "grains"));
    EXPECT_TRUE(is_int(p, "incline"));
  }
  const std::string pack = dir / "pack.h5";
  ASSERT_EQ(run_tool("gf-pack", "--grains 30 --packing-fraction 0.5 --mean-diameter 1 --quiet -o " + pack).exit_code,
            0);
  const io::Parameters pp = parameters_of(pack);
  EXPECT_TRUE(is_double(pp, "mean-diameter"));
  EXPECT_DOUBLE_EQ(pp.get_double("mean-diameter"), 1.0);
  EXPECT_TRUE(is_double(pp, "tolerance"));

  const std::string run = dir / "run.h5";
  auto r = run_tool("gf-shear", "-i " + pack + " --rate 1 --friction 0 --steps 20 --quiet -o " + run);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Parameters p = parameters_of(run);
  for (const char* name :
       {"rate", "friction", "restitution", "tangential-restitution", "tolerance", "checkpoint-every"})
    EXPECT_TRUE(is_double(p, name)) << name;
  for (const char* name : {"steps", "frame", "max-iterations", "threads", "observe-every", "frame-every", "resume"})
    EXPECT_TRUE(is_int(p, name)) << name;
  EXPECT_TRUE(std::holds_alternative<std::string>(p.items().at("output")));
}

TEST(GfShearProvenance, StrainAndStrainStepAreTheOnesUsed) {
  ScratchDir dir("prov_shear_used");
  const std::string run = dir / "run.h5";
  auto r = run_tool("gf-shear", "-i " + biperiodic() + " --rate 2 --steps 30 --dt 1e-3 --quiet -o " + run);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const io::Parameters p = parameters_of(run);
  EXPECT_DOUBLE_EQ(p.get_double("strain"), 30 * 2 * 1e-3);
  EXPECT_DOUBLE_EQ(p.get_double("strain-step"), 2 * 1e-3);
}

// The default sweep cap depends on the friction (frictional steps near jamming converge only
// after 10^4-10^5 sweeps); /parameters records the cap in force, given or not.
TEST(GfShearProvenance, SweepCapRecordedAsUsed) {
  ScratchDir dir("prov_sweep_cap");
  const std::string base = "-i " + biperiodic() + " --rate 1 --steps 5 --quiet -o ";
  const std::pair<std::string, std::int64_t> cases[] = {{"--friction 0", 10000},
                                                        {"--friction 0.4", 100000},
                                                        {"--friction 0.4 --max-iterations 300", 300},
                                                        {"--friction 0 --max-iterations 20000", 20000}};
  int k = 0;
  for (const auto& [options, cap] : cases) {
    const std::string out = dir / ("run" + std::to_string(k++) + ".h5");
    auto r = run_tool("gf-shear", base + out + " " + options);
    ASSERT_EQ(r.exit_code, 0) << options << ": " << r.err;
    EXPECT_EQ(parameters_of(out).get_int("max-iterations"), cap) << options;
  }
  for (const char* bad : {"0", "-5", "2000000000"}) {
    auto r = run_tool("gf-shear", base + (dir / "bad.h5") + " --friction 0.4 --max-iterations " + bad);
    EXPECT_EQ(r.exit_code, 2) << bad;
    EXPECT_NE(r.err.find("--max-iterations"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad.h5"));
  }
  // gf-incline takes the same rule.
  const std::string branch = dir / "incline.h5";
  auto r = run_tool("gf-incline",
                    "-i " + incline() + " --angle 20 --friction 0.4 --steps 5 --profile-block 5 --quiet -o " + branch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(parameters_of(branch).get_int("max-iterations"), 100000);
}

TEST(GfInclineProvenance, BranchOfABranchNamesItsParent) {
  ScratchDir dir("prov_branch");
  const std::string run = " --steps 20 --profile-block 10 --quiet";
  const std::string a = dir / "a.h5", b = dir / "b.h5", c = dir / "c.h5";
  auto ra = run_tool("gf-incline", "-i " + incline() + " --angle 20" + run + " -o " + a);
  ASSERT_EQ(ra.exit_code, 0) << ra.err;
  auto rb =
      run_tool("gf-incline", "-i " + a + " --angle 22 --friction 0.3 --restitution 0.7 --tangential-restitution 0.2" +
                                 run + " -o " + b);
  ASSERT_EQ(rb.exit_code, 0) << rb.err;
  auto rc = run_tool("gf-incline", "-i " + b + " --angle 24" + run + " -o " + c);
  ASSERT_EQ(rc.exit_code, 0) << rc.err;

  const io::Parameters pc = parameters_of(c);
  EXPECT_EQ(pc.get_string("parent_program"), "gf-incline");
  EXPECT_DOUBLE_EQ(pc.get_double("parent_angle"), 22);
  EXPECT_DOUBLE_EQ(pc.get_double("parent_friction"), 0.3);
  EXPECT_DOUBLE_EQ(pc.get_double("parent_restitution"), 0.7);
  EXPECT_DOUBLE_EQ(pc.get_double("parent_tangential-restitution"), 0.2);
  EXPECT_EQ(pc.get_string("parent_input"), a);
  EXPECT_EQ(pc.get_string("parent_input_sha256"), parameters_of(b).get_string("input_sha256"));
  // Every parent_* key is a key of the parent's /parameters.
  const io::Parameters pb = parameters_of(b);
  for (const auto& [name, value] : pc.items()) {
    if (name.rfind("parent_", 0) == 0) {
      EXPECT_TRUE(pb.has(name.substr(7))) << name;
    }
  }
}

class ProvenanceRefusal : public ::testing::TestWithParam<std::pair<const char*, BadInput>> {};

TEST_P(ProvenanceRefusal, OptionThatCannotApplyIsRefused) {
  const auto& [tool, c] = GetParam();
  expect_refused(tool, c, {{"{pack}", biperiodic()}, {"{incline}", incline()}});
}

std::string refusal_name(const ::testing::TestParamInfo<std::pair<const char*, BadInput>>& info) {
  std::string tool = info.param.first;
  for (auto& ch : tool)
    if (ch == '-') ch = '_';
  return tool + "_" + info.param.second.name;
}

INSTANTIATE_TEST_SUITE_P(
    Programs, ProvenanceRefusal,
    ::testing::Values(
        std::make_pair("gf-pack", BadInput{"grains_with_input", "-i {pack} --grains 100 -o {out}",
                                           "--grains cannot be combined with --input"}),
        std::make_pair("gf-pack", BadInput{"seed_with_input", "-i {pack} --seed 3 -o {out}",
                                           "--seed cannot be combined with --input"}),
        std::make_pair("gf-pack", BadInput{"polydispersity_with_input", "-i {pack} --polydispersity 0.1 -o {out}",
                                           "--polydispersity cannot be combined with --input"}),
        std::make_pair("gf-pack", BadInput{"diameter_with_input", "-i {pack} --mean-diameter 1 -o {out}",
                                           "--mean-diameter cannot be combined with --input"}),
        std::make_pair("gf-pack", BadInput{"frame_without_input", "--frame 0 -o {out}", "--frame needs --input"}),
        std::make_pair("gf-pack", BadInput{"width_without_incline", "--width 10 -o {out}", "--width needs --incline"}),
        std::make_pair("gf-pack",
                       BadInput{"height_without_incline", "--height 10 -o {out}", "--height needs --incline"}),
        std::make_pair("gf-pack", BadInput{"fraction_with_incline", "--incline --packing-fraction 0.5 -o {out}",
                                           "--packing-fraction cannot be combined with --incline"}),
        std::make_pair("gf-pack", BadInput{"tolerance_with_incline", "--incline --tolerance 1e-6 -o {out}",
                                           "--tolerance cannot be combined with --incline"}),
        std::make_pair("gf-pack", BadInput{"input_with_incline", "--incline -i {pack} -o {out}",
                                           "--input cannot be combined with --incline"}),
        std::make_pair("gf-pack", BadInput{"height_with_grains", "--incline --grains 30 --height 4 -o {out}",
                                           "--height cannot be combined with --grains"}),
        std::make_pair("gf-shear", BadInput{"strain_with_steps", "-i {pack} --strain 5 --steps 10 -o {out}",
                                            "--strain cannot be combined with --steps"}),
        std::make_pair("gf-shear", BadInput{"strain_step_with_dt", "-i {pack} --strain-step 1e-3 --dt 1e-3 -o {out}",
                                            "--strain-step cannot be combined with --dt"}),
        std::make_pair("gf-shear", BadInput{"temperature_with_rate", "-i {pack} --rate 1 --temperature 2 -o {out}",
                                            "--temperature cannot be combined with --rate 1"}),
        std::make_pair("gf-incline", BadInput{"time_with_steps", "-i {incline} --angle 20 --time 5 --steps 10 -o {out}",
                                              "--time cannot be combined with --steps"}),
        std::make_pair("gf-incline",
                       BadInput{"time_step_with_dt", "-i {incline} --angle 20 --time-step 1e-3 --dt 1e-3 -o {out}",
                                "--time-step cannot be combined with --dt"})),
    refusal_name);

TEST(ProgramHelp, EveryLineFitsOneHundredColumns) {
  for (const char* tool : {"gf-pack", "gf-shear", "gf-incline", "gf-correlate", "gf-kinetic", "gf-xdmf"}) {
    const std::string help = stdout_of(tool_path(tool) + " --help");
    ASSERT_NE(help.find("Options:"), std::string::npos) << tool;
    std::size_t start = 0;
    for (std::size_t end; (end = help.find('\n', start)) != std::string::npos; start = end + 1) {
      const std::string line = help.substr(start, end - start);
      EXPECT_LE(code_points(line), 100u) << tool << ": " << line;
    }
  }
}
