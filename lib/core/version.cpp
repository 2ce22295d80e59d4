#include "core/version.hpp"

#include <cstring>

// Defined in the generated translation unit, which is never seen from here: the
// compiler cannot fold the text into code, so it stays only in section .gfversion.
extern "C" const char granflow_version_text[96];

namespace granflow {
std::string version() { return std::string(granflow_version_text, strnlen(granflow_version_text, 96)); }
}  // namespace granflow
