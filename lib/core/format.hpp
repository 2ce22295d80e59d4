#pragma once
// Numbers in messages and attributes: printf's %g with a given number of significant digits
// (6, the default, is what a reader wants in a message; 17 round-trips a double exactly).
#include <cstdio>
#include <string>

namespace granflow {

inline std::string format_number(double x, int significant = 6) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", significant, x);
  return buffer;
}

}  // namespace granflow
