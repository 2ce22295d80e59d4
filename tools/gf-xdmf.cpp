// gf-xdmf: an XDMF description of a trajectory for ParaView, beside it, pointing into its
// datasets (docs/programs/gf-xdmf.md).
#include <cstdio>
#include <filesystem>

#include "core/cli.hpp"
#include "core/error.hpp"
#include "core/output_file.hpp"
#include "core/signals.hpp"
#include "core/tool.hpp"
#include "io/trajectory.hpp"
#include "io/xdmf.hpp"

using namespace granflow;
namespace fs = std::filesystem;

namespace {

// RUN.h5 -> RUN.xdmf2 (any other name: NAME.xdmf2). ParaView opens .xdmf2 with its XDMF 2
// reader without asking; for .xdmf it asks in the GUI and takes an Xdmf3 reader in scripts,
// which ParaView 5.11 ends with a segmentation fault on these files.
std::string default_output(const std::string& input) {
  fs::path p(input);
  if (p.extension() == ".h5") return p.replace_extension(".xdmf2").string();
  return input + ".xdmf2";
}

// The trajectory as the XDMF file names it: relative to the XDMF file's directory, so the
// pair can move together (just the file name when they sit side by side). Both paths with
// symbolic links resolved, as the system resolves "dir/../x" when ParaView opens it.
std::string name_from(const std::string& output, const std::string& input) {
  std::error_code ec;
  const fs::path dir = fs::weakly_canonical(fs::absolute(fs::path(output)), ec).parent_path();
  const fs::path trajectory = fs::weakly_canonical(fs::absolute(fs::path(input)), ec);
  const fs::path relative = ec ? fs::path() : trajectory.lexically_relative(dir);
  const std::string name = relative.empty() ? fs::absolute(fs::path(input)).string() : relative.string();
  // XDMF 2 separates the file from the dataset at the first colon.
  if (name.find(':') != std::string::npos)
    throw UsageError("'" + input + "': an XDMF file cannot name a trajectory whose path contains ':' ('" + name +
                     "'); rename or move it");
  return name;
}

}  // namespace

int main(int argc, char** argv) {
  return run_tool("gf-xdmf", [&] {
    CommandLine cli("gf-xdmf", "-i RUN.h5 [-o RUN.xdmf2] [options]",
                    "An XDMF 2 description of a trajectory (any granflow trajectory or packing) for ParaView:\n"
                    "grains as points with radius, mass, fixed, velocity, angular_velocity and orientation; the\n"
                    "contacts of each stored frame as segments from r_i to r_i - branch with normal_force,\n"
                    "tangential_force, binary_force (F_bc) and age; the box outline with the Lees-Edwards offset.\n"
                    "One grid per stored frame, in time. Every array is a reference into the trajectory's\n"
                    "datasets, which the XDMF names relative to itself: keep the two files together. ParaView\n"
                    "opens a .xdmf2 file with its \"Xdmf Reader\" (XDMF 2); for another name choose that reader\n"
                    "(docs/programs/gf-xdmf.md).");
    cli.text_option("input", 'i', "FILE", "the trajectory (HDF5, docs/file-format.md)");
    cli.text_option("output", 'o', "FILE",
                    "the XDMF file to write; default: the input with .h5 replaced by .xdmf2, beside it");
    if (!cli.parse(argc, argv)) return 0;
    if (!cli.has("input")) throw UsageError("option --input: a trajectory is required (-i RUN.h5)");
    const std::string input = cli.text("input");
    const std::string output = cli.has("output") ? cli.text("output") : default_output(input);

    io::TrajectoryReader reader(input);
    refuse_output_among_inputs(output, {input});
    OutputFile out(output);
    const std::string h5_name = name_from(output, input);
    io::XdmfSummary summary;
    const std::string text = io::xdmf_description(reader, h5_name, &summary);
    out.write_text(text);
    check_interrupt();
    out.commit();
    if (!cli.flag_set("quiet"))
      std::fprintf(stderr, "gf-xdmf: %s: %zu frame(s), %zu grains, %zu contacts, referencing '%s'\n", output.c_str(),
                   summary.frames, summary.grains, summary.contacts, h5_name.c_str());
    return 0;
  });
}
