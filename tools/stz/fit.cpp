// gf-stz fit: placeholder until the command is written (refuses every call but --help).
#include "core/cli.hpp"
#include "core/error.hpp"
#include "stz/commands.hpp"

namespace granflow::stz_tool {

int fit_command(int argc, char** argv) {
  CommandLine cli("gf-stz fit", "[options]", "Not written yet.");
  cli.text_option("output", 'o', "FILE", "output HDF5 file");
  if (!cli.parse(argc, argv)) return 0;
  throw UsageError("gf-stz fit is not written yet");
}

}  // namespace granflow::stz_tool
