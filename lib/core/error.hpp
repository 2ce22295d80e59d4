#pragma once
// Errors carry the exit code the tools must return (docs/file-format.md, Exit codes: 1 runtime,
// 2 bad usage/input).
#include <stdexcept>
#include <string>

namespace granflow {

// Bad command line or bad/invalid input file: exit code 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// Failure while running on valid input (I/O error mid-run, non-finite state...): exit code 1.
struct RuntimeFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};
// A file could not be written or closed (a full file system, a quota, an I/O error): exit
// code 1. A resumable run keeps its last checkpoint and partial output (run/runner.hpp).
struct WriteFailure : RuntimeFailure {
  using RuntimeFailure::RuntimeFailure;
};
// SIGINT/SIGTERM reached a long loop: exit code 1 after cleaning up.
struct Interrupted : std::runtime_error {
  explicit Interrupted(const std::string& what = "interrupted by signal; no output written")
      : std::runtime_error(what) {}
};

}  // namespace granflow
