#pragma once
// Units of every dataset granflow writes (docs/file-format.md, Units), in one place.
// Files carry them as the H5MD units module asks: a `unit` attribute per dataset whose
// string is unit factors separated by spaces, each a symbol with an optional signed
// integer power ("L T-1"), "1" for a dimensionless number; trajectories declare the
// system in /h5md/modules/units. The symbols are granflow's reduced units:
//   L    the code length (grain radii are in L; the default mean diameter σ is 1.4 L)
//   M    the code mass (areal density 1: a grain of radius R has mass πR² M/L²)
//   T    the code time (gf-pack, gf-shear: the time of --dt and 1/γ̇)
//   tau  gf-incline's time τ = √(⟨R⟩/g) (its value in T is /parameters `tau`)
//   rad, deg  plane angles in radians, in degrees
#include <string>

#include "io/hdf5_handle.hpp"

namespace granflow::io {

// The value of /h5md/modules/units' `system` attribute.
inline constexpr const char* kUnitSystem = "granflow reduced";
// The H5MD unit of gf-incline's τ; the code time's, "T", is io::kCodeTime
// (io/trajectory.hpp), the default of every trajectory's TimeUnit.
inline constexpr const char* kTauUnit = "tau";

// The H5MD unit string of a quantity named in words: products (·) and one quotient (/)
// of length, mass, time, velocity, force, tau, radian, degrees, each with an optional
// power (², ³, ^n); "1" for a number; a parenthesised remark is ignored. E.g.
// "force/length (2D stress)" → "M T-2", "mass·velocity²" → "M L+2 T-2", "1/time" → "T-1".
// RuntimeFailure on any other word.
std::string unit_of(const std::string& quantity);

// Writes the `unit` attribute of a dataset as the module asks: a scalar, fixed-length
// string of the ASCII character set (granflow's other strings are UTF-8). Replaces an
// existing one.
void write_unit(hid_t dataset, const std::string& unit);

// Writes the H5MD units module into an /h5md group: /h5md/modules/units with `version`
// [1, 0] and `system`.
void write_units_module(hid_t h5md_group);

}  // namespace granflow::io
