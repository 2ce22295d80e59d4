#pragma once
#include <string>

namespace granflow {
// "granflow <project version> (<git describe>)", fixed at build time.
// The text lives in its own ELF section (.gfversion) of fixed size so that the
// pipeline's content-hash stamps can ignore it: a new commit that does not change
// a program's code must not make `make` re-run that program's simulations.
std::string version();

// The second line of every program's --version: the licence and how to cite.
inline constexpr const char* kLicenceLine =
    "Licence: BSD-3-Clause (the file LICENSE of the source). How to cite it: CITATION.cff.";
}  // namespace granflow
