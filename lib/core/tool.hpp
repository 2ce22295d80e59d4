#pragma once
// The common shell of every gf-* main(): exceptions become one clear line on stderr
// and the exit codes of docs/file-format.md (0 ok, 1 runtime failure, 2 bad usage/input).
#include <functional>

namespace granflow {

int run_tool(const char* program, const std::function<int()>& body);

// A library was left unable to clean up (HDF5 after a failed H5Fclose: its exit handler
// would close the half-closed file again and crash): run_tool ends the process with
// _exit once its message is printed and the body's destructors have run.
void skip_exit_handlers();
bool exit_handlers_skipped();

}  // namespace granflow
