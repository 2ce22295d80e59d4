#include "core/tool.hpp"

#include <link.h>
#include <sys/auxv.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <exception>

#include "core/error.hpp"
#include "core/signals.hpp"

namespace granflow {

namespace {

// OpenMP's wait policy. With more threads than free cores, libgomp's default (spin 300000
// times at every barrier before sleeping) makes --threads 2 tens of times slower than one
// thread; sleeping at once (OMP_WAIT_POLICY=passive) costs a system call per barrier. A
// short spin, GOMP_SPINCOUNT=10000 (the tests' value, tests/CMakeLists.txt), keeps an idle
// machine fast and a busy one several times less slow (docs/performance.md). libgomp
// reads its environment in its initialiser, before main() and before anything an
// executable can run except its .preinit_array; and a variable set there does not reach
// it (the C library's own initialiser, which runs in between, resets the environment to
// the one the process started with). So a program that loads libgomp and was started
// without the variable runs itself again, at once, with it added: nothing has been opened
// or started yet, and the process keeps its id, arguments, descriptors and signal
// dispositions. A user who sets GOMP_SPINCOUNT or OMP_WAIT_POLICY keeps that choice.
// Programs without threads (no libgomp loaded) and other OpenMP runtimes (Clang's libomp
// has no GOMP_SPINCOUNT) are left alone.
#if defined(__linux__)
bool has_variable(char** envp, const char* prefix) {
  const std::size_t n = std::strlen(prefix);
  for (char** e = envp; e != nullptr && *e != nullptr; ++e)
    if (std::strncmp(*e, prefix, n) == 0) return true;
  return false;
}

bool libgomp_loaded() {
  return ::dl_iterate_phdr(
             [](dl_phdr_info* info, std::size_t, void*) {
               return info->dlpi_name != nullptr && std::strstr(info->dlpi_name, "/libgomp.so") != nullptr ? 1 : 0;
             },
             nullptr) != 0;
}

void set_omp_wait_policy(int /*argc*/, char** argv, char** envp) {
  if (has_variable(envp, "GOMP_SPINCOUNT=") || has_variable(envp, "OMP_WAIT_POLICY=") || !libgomp_loaded()) return;
  // No allocation this early: a fixed table, and no change when the environment is larger.
  static char spin[] = "GOMP_SPINCOUNT=10000";
  static char* env[4096];
  std::size_t n = 0;
  for (char** e = envp; e != nullptr && *e != nullptr; ++e) {
    if (n + 2 >= sizeof env / sizeof env[0]) return;
    env[n++] = *e;
  }
  env[n++] = spin;
  env[n] = nullptr;
  ::execve("/proc/self/exe", argv, env);
  // Without /proc: the path this process was started from.
  if (const char* path = reinterpret_cast<const char*>(::getauxval(AT_EXECFN)); path != nullptr)
    ::execve(path, argv, env);
  // Both failed: run on with libgomp's default.
}

// Linked into every program through run_tool, which this file defines.
[[gnu::section(".preinit_array"), gnu::used]] void (*const preinit_omp_wait_policy)(int, char**,
                                                                                    char**) = set_omp_wait_policy;
#endif

bool skip_handlers = false;

int run_body(const char* program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 2;
  } catch (const Interrupted& e) {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: failure: %s\n", program, e.what());
    return 1;
  }
}

}  // namespace

void skip_exit_handlers() { skip_handlers = true; }
bool exit_handlers_skipped() { return skip_handlers; }

int run_tool(const char* program, const std::function<int()>& body) {
  install_interrupt_handlers();
  const int code = run_body(program, body);
  if (skip_handlers) {
    std::fflush(nullptr);
    ::_exit(code);
  }
  return code;
}

}  // namespace granflow
