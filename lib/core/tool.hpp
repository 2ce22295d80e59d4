#pragma once
// The common shell of every gf-* main(): exceptions become one clear line on stderr
// and the exit codes of docs/file-format.md (0 ok, 1 runtime failure, 2 bad usage/input).
#include <functional>

namespace granflow {

int run_tool(const char* program, const std::function<int()>& body);

}  // namespace granflow
