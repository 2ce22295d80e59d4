#pragma once
// The commands of gf-stz. Each parses its own options (argv[0] is the command's name) and
// returns the exit code; errors are thrown, as in every gf-* main (core/tool.hpp).
namespace granflow::stz_tool {

int d2min_command(int argc, char** argv);
int fit_command(int argc, char** argv);

}  // namespace granflow::stz_tool
