// Unit tests for lib/core: command line, SHA-256, atomic outputs.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "core/cli.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/sha256.hpp"

using namespace granflow;

namespace {
CommandLine make_cli() {
  CommandLine cli("gf-test", "[options]", "test program");
  cli.integer_option("grains", 'n', "N", "number of grains", "100");
  cli.real_option("rate", 0, "RATE", "shear rate");
  cli.flag("incline", 0, "incline mode");
  return cli;
}
bool parse(CommandLine& cli, std::vector<const char*> args) {
  args.insert(args.begin(), "gf-test");
  return cli.parse(int(args.size()), args.data());
}
}  // namespace

TEST(CoreCli, DefaultsAndValues) {
  auto cli = make_cli();
  ASSERT_TRUE(parse(cli, {"--rate", "-0.5", "--incline"}));
  EXPECT_EQ(cli.integer("grains"), 100);
  EXPECT_DOUBLE_EQ(cli.real("rate"), -0.5);
  EXPECT_TRUE(cli.flag_set("incline"));
  EXPECT_TRUE(cli.given("rate"));
  EXPECT_FALSE(cli.given("grains"));
}

TEST(CoreCli, ShortAndInlineForms) {
  auto cli = make_cli();
  ASSERT_TRUE(parse(cli, {"-n", "1e4", "--rate=2"}));
  EXPECT_EQ(cli.integer("grains"), 10000);
  EXPECT_DOUBLE_EQ(cli.real("rate"), 2.0);
}

TEST(CoreCli, ErrorsNameTheOption) {
  auto cli = make_cli();
  try {
    parse(cli, {"--bogus"});
    FAIL() << "unknown option accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--bogus"), std::string::npos);
  }
  auto cli2 = make_cli();
  ASSERT_TRUE(parse(cli2, {"--grains", "12.5", "--rate", "nan"}));
  EXPECT_THROW(cli2.integer("grains"), UsageError);
  EXPECT_THROW(cli2.real("rate"), UsageError);
  auto cli3 = make_cli();
  ASSERT_TRUE(parse(cli3, {}));
  EXPECT_THROW(cli3.real("rate"), UsageError);  // required, no default
  auto cli4 = make_cli();
  EXPECT_THROW(parse(cli4, {"--rate"}), UsageError);  // missing value
  auto cli5 = make_cli();
  EXPECT_THROW(parse(cli5, {"stray"}), UsageError);  // no positionals declared
}

TEST(CoreCli, HelpListsEveryOptionWithDefault) {
  auto cli = make_cli();
  std::string h = cli.help();
  for (const char* name : {"--grains", "--rate", "--incline", "--help", "--version", "--quiet"})
    EXPECT_NE(h.find(name), std::string::npos) << name;
  EXPECT_NE(h.find("[default: 100]"), std::string::npos);
}

TEST(CoreCli, ReadingAnotherKindIsAProgrammingError) {
  auto cli = make_cli();
  ASSERT_TRUE(parse(cli, {"--rate", "2", "--incline"}));
  EXPECT_THROW(cli.real("grains"), std::logic_error);
  EXPECT_THROW(cli.integer("rate"), std::logic_error);
  EXPECT_THROW(cli.flag_set("rate"), std::logic_error);
  EXPECT_THROW(cli.text("incline"), std::logic_error);
  EXPECT_EQ(cli.text("rate"), "2");  // the typed form of a number
  EXPECT_EQ(cli.kind("rate"), OptionKind::real);
  EXPECT_EQ(cli.kind("grains"), OptionKind::integer);
  EXPECT_EQ(cli.kind("incline"), OptionKind::flag);
  CommandLine twice("gf-test", "", "");
  twice.real_option("rate", 0, "R", "rate");
  EXPECT_THROW(twice.integer_option("rate", 0, "R", "rate"), std::logic_error);
}

namespace {
CommandLine related_cli() {
  CommandLine cli = make_cli();
  cli.text_option("input", 'i', "FILE", "input");
  cli.real_option("width", 0, "W", "incline width", "40");
  cli.conflicts("grains", "input");
  cli.needs("width", "incline");
  return cli;
}
std::string usage_error(CommandLine& cli, std::vector<const char*> args) {
  try {
    parse(cli, std::move(args));
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}
bool has_value(const CommandLine& cli, const std::string& name) {
  for (const auto& [n, v] : cli.values())
    if (n == name) return true;
  return false;
}
}  // namespace

TEST(CoreCli, OptionsThatCannotApplyAreRefusedNamingBoth) {
  auto a = related_cli();
  EXPECT_EQ(usage_error(a, {"-n", "5", "-i", "x.h5"}), "option --grains cannot be combined with --input");
  auto b = related_cli();
  EXPECT_EQ(usage_error(b, {"--width", "5"}), "option --width needs --incline");
  auto c = related_cli();
  ASSERT_TRUE(parse(c, {"--width", "5", "--incline", "-n", "3"}));
  EXPECT_TRUE(has_value(c, "width"));
  EXPECT_TRUE(has_value(c, "grains"));
  // A default never conflicts, and an option that does not apply is not a value of the run.
  auto d = related_cli();
  ASSERT_TRUE(parse(d, {"-i", "x.h5"}));
  EXPECT_FALSE(has_value(d, "grains"));
  EXPECT_FALSE(has_value(d, "width"));
  EXPECT_EQ(d.integer("grains"), 100);
  auto e = related_cli();
  ASSERT_TRUE(parse(e, {"--rate", "1"}));
  e.not_applicable("grains", "--rate 1");
  EXPECT_FALSE(has_value(e, "grains"));
  auto f = related_cli();
  ASSERT_TRUE(parse(f, {"--rate", "1", "-n", "4"}));
  try {
    f.not_applicable("grains", "--rate 1");
    FAIL() << "a given option that does not apply was accepted";
  } catch (const UsageError& err) {
    EXPECT_EQ(std::string(err.what()), "option --grains cannot be combined with --rate 1");
  }
}

TEST(CoreCli, HelpIsWrappedToOneHundredColumns) {
  CommandLine cli("gf-test", "[options]", "A description\nof two lines.");
  std::string words;
  for (int k = 0; k < 60; ++k) words += "γ̇σθ word ";
  cli.real_option("long", 0, "X", words + "see --other-option for more\nthen a line of its own", "1");
  cli.flag("other-option", 0, "short");
  const std::string h = cli.help();
  EXPECT_NE(h.find("A description\nof two lines.\n"), std::string::npos);
  EXPECT_NE(h.find("\n          then a line of its own [default: 1]\n"), std::string::npos);
  // A long-only option's description is indented apart from its name.
  EXPECT_NE(h.find("\n      --other-option\n          short\n"), std::string::npos);
  EXPECT_NE(h.find(std::string("\n") + CommandLine::kExitStatusLine + "\n"), std::string::npos);
  int lines_of_long = 0;
  std::size_t start = 0;
  for (std::size_t end; (end = h.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string line = h.substr(start, end - start);
    std::size_t columns = 0;
    for (unsigned char ch : line) columns += (ch & 0xC0) != 0x80;
    EXPECT_LE(columns, CommandLine::kHelpWidth) << line;
    // No continuation line starts like an option line: those are the options' own.
    if (line.rfind("      --", 0) == 0 && line != "      --version" && line != "      --long <X>" &&
        line != "      --other-option")
      ADD_FAILURE() << line;
    if (line.find("word") != std::string::npos) ++lines_of_long;
  }
  EXPECT_GT(lines_of_long, 5);
  EXPECT_NE(h.find("  --other-option\n"), std::string::npos);
}

TEST(CoreCli, CommandLineIsShellQuoted) {
  auto cli = make_cli();
  ASSERT_TRUE(parse(cli, {"--rate", "it's 1"}));
  EXPECT_EQ(cli.command_line(), "gf-test --rate 'it'\\''s 1'");
}

TEST(CoreRange, Checks) {
  EXPECT_NO_THROW(require_in_range("packing-fraction", 0.5, 0, 0.91, true, true));
  EXPECT_THROW(require_in_range("packing-fraction", 0.0, 0, 0.91, true, true), UsageError);
  EXPECT_THROW(require_in_range("packing-fraction", 0.91, 0, 0.91, true, true), UsageError);
  EXPECT_NO_THROW(require_in_range("restitution", 1.0, 0, 1, false, false));
  EXPECT_THROW(require_positive("dt", 0.0), UsageError);
}

TEST(CoreSha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(CoreOutputFile, CommitRenamesAndAbandonRemoves) {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / "granflow_test_output_file";
  fs::create_directories(dir);
  std::string final_path = (dir / "out.h5").string();
  fs::remove(final_path);
  std::string temp;
  {
    OutputFile out(final_path);
    temp = out.temp_path();
    std::ofstream(temp) << "partial";
    EXPECT_TRUE(fs::exists(temp));
  }
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_FALSE(fs::exists(final_path));
  {
    OutputFile out(final_path);
    std::ofstream(out.temp_path()) << "done";
    out.commit();
  }
  EXPECT_TRUE(fs::exists(final_path));
  EXPECT_THROW(OutputFile((dir / "missing_dir" / "x.h5").string()), UsageError);
  EXPECT_THROW(OutputFile(dir.string()), UsageError);
  fs::remove_all(dir);
}

TEST(CoreCli, TextListSplitsAtCommasAndRefusesWhatItCannotSplit) {
  auto given = related_cli();
  ASSERT_TRUE(parse(given, {"-i", "a.h5,b.h5"}));
  EXPECT_EQ(given.text_list("input"), (std::vector<std::string>{"a.h5", "b.h5"}));
  auto absent = related_cli();
  ASSERT_TRUE(parse(absent, {}));
  EXPECT_TRUE(absent.text_list("input").empty());
  auto commas = related_cli();
  ASSERT_TRUE(parse(commas, {"-i", ","}));
  EXPECT_TRUE(commas.text_list("input").empty());
  auto refused = [](std::vector<const char*> args, const std::string& piece) {
    auto cli = related_cli();
    ASSERT_TRUE(parse(cli, args));
    try {
      cli.text_list("input");
      ADD_FAILURE() << "no UsageError for " << piece;
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("option --input: " + piece), std::string::npos) << e.what();
    }
  };
  refused({"-i", "a.h5,,b.h5"}, "item 2 of 'a.h5,,b.h5' is empty");
  refused({"-i", "a.h5,"}, "item 2 of 'a.h5,' is empty");
  refused({"-i", ",a.h5"}, "item 1 of ',a.h5' is empty");
  refused({"-i", "a.h5", "--input", "b.h5"}, "given 2 times");
  const auto dir = std::filesystem::temp_directory_path() / ("granflow_text_list_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string named = (dir / "run,1.h5").string(), listed = named + "," + (dir / "b.h5").string();
  std::ofstream(named) << "x";
  refused({"-i", listed.c_str()}, "'" + named + "' contains a comma");
  std::filesystem::remove_all(dir);
}
