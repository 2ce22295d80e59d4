// gf-stz d2min: D²min (thesis eq. 6.32) of every grain between two stored frames of a gf-shear
// trajectory, or between a frame of it and a frame of a branch started from that frame
// (lib/stz/d2min_file.hpp).
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/cli.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/signals.hpp"
#include "io/provenance.hpp"
#include "stz/commands.hpp"
#include "stz/d2min_file.hpp"

namespace granflow::stz_tool {

namespace {

bool is_integer(const std::string& s) {
  std::size_t k = (!s.empty() && s[0] == '-') ? 1 : 0;
  if (k == s.size()) return false;
  for (; k < s.size(); ++k)
    if (!std::isdigit(static_cast<unsigned char>(s[k]))) return false;
  return true;
}

// `--frames A B` as `--frames A,B`: one option of the command line takes one value.
std::vector<std::string> join_frames(int argc, char** argv) {
  std::vector<std::string> args(argv, argv + argc);
  for (std::size_t k = 1; k + 1 < args.size(); ++k) {
    const bool separate = args[k] == "--frames" && k + 2 < args.size();
    const bool inline_value = args[k].rfind("--frames=", 0) == 0;
    if (separate && args[k + 1].find(',') == std::string::npos && is_integer(args[k + 2])) {
      args[k + 1] += "," + args[k + 2];
      args.erase(args.begin() + std::ptrdiff_t(k) + 2);
    } else if (inline_value && args[k].find(',') == std::string::npos && is_integer(args[k + 1])) {
      args[k] += "," + args[k + 1];
      args.erase(args.begin() + std::ptrdiff_t(k) + 1);
    }
    if (args[k] == "--") break;
  }
  return args;
}

long long frame_of(const std::string& text) {
  if (!is_integer(text) || text.size() > 18) throw UsageError("option --frames: '" + text + "' is not a frame index");
  return std::stoll(text);
}

}  // namespace

int d2min_command(int argc, char** argv) {
  CommandLine cli("gf-stz d2min", "-i TRAJ.h5 --frames A B [--branch BRANCH.h5] [--cutoff C] -o OUT.h5",
                  "D²min (thesis eq. 6.32, Falk-Langer) of every grain between two stored frames: frame A of TRAJ\n"
                  "(the reference) and frame B of TRAJ, or frame B of BRANCH, a gf-shear run started from frame A\n"
                  "of TRAJ (gf-shear -i TRAJ --frame A, e.g. sheared the other way). Neighbours: every grain whose\n"
                  "centre is closer than C mean diameters in frame A (Lees-Edwards minimum image). Current bonds\n"
                  "follow the unwrapped displacements over every stored frame in between, never a minimum image at\n"
                  "the later time, so wrapped offsets, strains above 1 and negative rates are all right. Per grain:\n"
                  "D²min (the sum over the neighbours), D²min per neighbour, the fitted F, the neighbour count, and\n"
                  "valid = 0 (NaN values) where fewer than 2 neighbours or collinear ones leave F undetermined.\n"
                  "Output: docs/file-format.md, gf-stz d2min output.");
  cli.text_option("input", 'i', "TRAJ", "gf-shear trajectory holding the reference frame A");
  cli.text_option("frames", 0, "A B",
                  "the reference frame A (of TRAJ) and the current frame B (of TRAJ, or of BRANCH), two indices or "
                  "A,B; negative counts from the end; B before A maps backwards in time; A = B gives D²min = 0");
  cli.text_option("branch", 0, "BRANCH",
                  "gf-shear run started from frame A of TRAJ (gf-shear -i TRAJ --frame A): frame B is its frame");
  cli.real_option("cutoff", 0, "C",
                  "neighbours: centre distance < C mean diameters (2<R> over the grains), the same for every pair",
                  "2");
  cli.text_option("output", 'o', "FILE", "output HDF5 file");
  const std::vector<std::string> args = join_frames(argc, argv);
  std::vector<const char*> pointers;
  for (const std::string& a : args) pointers.push_back(a.c_str());
  if (!cli.parse(int(pointers.size()), pointers.data())) return 0;

  stz::D2minRequest request;
  if (!cli.given("input")) throw UsageError("option --input: no trajectory given (-i TRAJ.h5)");
  if (!cli.given("frames")) throw UsageError("option --frames: give the two frames, --frames A B");
  if (!cli.given("output")) throw UsageError("option --output: no output file given (-o OUT.h5)");
  request.trajectory = cli.text("input");
  const std::string frames = cli.text("frames");
  const std::size_t comma = frames.find(',');
  if (comma == std::string::npos || frames.find(',', comma + 1) != std::string::npos)
    throw UsageError("option --frames: give two frames, A B or A,B; got '" + frames + "'");
  request.reference_frame = frame_of(frames.substr(0, comma));
  request.current_frame = frame_of(frames.substr(comma + 1));
  if (cli.given("branch")) {
    request.branch = cli.text("branch");
    if (request.branch.empty()) throw UsageError("option --branch: no file given");
  }
  request.cutoff_diameters = cli.real("cutoff");
  request.quiet = cli.flag_set("quiet");

  refuse_output_among_inputs(cli.text("output"), {request.trajectory, request.branch});
  OutputFile out(cli.text("output"));
  const stz::D2minResult result = stz::d2min_between_frames(request);
  io::Parameters parameters = io::provenance(cli);
  parameters.set("program", "gf-stz");
  parameters.set("command", "d2min");
  parameters.set("command_line", "gf-stz " + cli.command_line());
  io::add_hashed_input(parameters, request.trajectory, result.trajectory_sha256);
  if (!request.branch.empty()) io::add_input(parameters, request.branch, 0, "branch");
  stz::write_d2min(out.temp_path(), result, parameters);
  check_interrupt();
  out.commit();

  if (!request.quiet) {
    double sum = 0;
    for (std::size_t i = 0; i < result.d2min.valid.size(); ++i)
      if (result.d2min.valid[i]) sum += result.d2min.per_neighbour[i];
    const double mean = result.valid_count ? sum / double(result.valid_count) : NAN;
    std::fprintf(stderr,
                 "gf-stz d2min: %s frame %lld -> %s frame %lld: strain %.6g, %lld of %zu grains valid, mean D²min "
                 "per neighbour %.6g (cutoff %.4g)\n",
                 request.trajectory.c_str(), (long long)result.reference_frame,
                 (request.branch.empty() ? request.trajectory : request.branch).c_str(),
                 (long long)result.current_frame, result.strain, (long long)result.valid_count,
                 result.reference_position.size(), mean, result.cutoff);
  }
  return 0;
}

}  // namespace granflow::stz_tool
