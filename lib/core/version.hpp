#pragma once
#include <string>

namespace granflow {
// "granflow <project version> (<git describe>)", fixed at build time.
// The text lives in its own ELF section (.gfversion) of fixed size so that the
// pipeline's content-hash stamps can ignore it: a new commit that does not change
// a program's code must not make `make` re-run that program's simulations.
std::string version();
}  // namespace granflow
