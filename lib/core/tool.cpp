#include "core/tool.hpp"

#include <cstdio>
#include <exception>

#include "core/error.hpp"
#include "core/signals.hpp"

namespace granflow {

int run_tool(const char* program, const std::function<int()>& body) {
  install_interrupt_handlers();
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

}  // namespace granflow
