// gf-stz: non-affine motion (D²min, thesis eq. 6.32) and the STZ constitutive law (eqs.
// 6.33–6.36) over gf-shear and gf-incline results, thesis §6.3. Two commands, each a thin
// main of its own under tools/stz/, so that each keeps its options and its --help.
#include <cstdio>
#include <cstring>
#include <string>

#include "core/cli.hpp"
#include "core/error.hpp"
#include "core/tool.hpp"
#include "core/version.hpp"
#include "stz/commands.hpp"

using namespace granflow;

namespace {

void print_help() {
  std::printf(
      "Usage: gf-stz COMMAND [options]\n"
      "\n"
      "Non-affine motion and the shear-transformation-zone (STZ) law of thesis 6.3.\n"
      "\n"
      "Commands:\n"
      "  d2min    D²min (eq. 6.32) of every grain between two frames of a gf-shear trajectory, or\n"
      "           between a frame of it and a frame of a branch started from that frame\n"
      "  fit      the STZ law (eq. 6.36) and μ(I) fitted to steady shear runs, per friction\n"
      "           coefficient, and their predictions for the other runs and incline flows\n"
      "\n"
      "`gf-stz COMMAND --help` lists the options of a command.\n"
      "\n"
      "Options:\n"
      "  -h, --help\n"
      "          print this help and exit\n"
      "      --version\n"
      "          print the program version and exit\n"
      "\n%s\n",
      CommandLine::kExitStatusLine);
}

}  // namespace

int main(int argc, char** argv) {
  return run_tool("gf-stz", [&]() -> int {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command == "-h" || command == "--help") {
      print_help();
      return 0;
    }
    if (command == "--version") {
      std::printf("gf-stz %s\n%s\n", version().c_str(), kLicenceLine);
      return 0;
    }
    if (command == "d2min") return stz_tool::d2min_command(argc - 1, argv + 1);
    if (command == "fit") return stz_tool::fit_command(argc - 1, argv + 1);
    if (command.empty()) throw UsageError("no command: gf-stz d2min ... or gf-stz fit ... (gf-stz --help)");
    throw UsageError("unknown command '" + command + "': gf-stz d2min ... or gf-stz fit ... (gf-stz --help)");
  });
}
