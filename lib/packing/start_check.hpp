#pragma once
// What every program that starts from stored grains (gf-pack --input, gf-shear -i,
// gf-incline -i) checks beyond the single values the reader checks (docs/file-format.md,
// Reading errors): the grains' geometry, and that a run's trajectory kept its contacts.
#include <cstddef>
#include <string>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"
#include "io/trajectory.hpp"

namespace granflow {

// Overlaps above this share of the smaller radius are refused: packings and stored frames
// of valid runs overlap by less than 1e-7 of it, gf-pack at ν = 0.9 leaves about 0.2, and a
// grain sunk by more than half its radius into another is a broken file or a run that
// diverged, from which no start is meaningful.
inline constexpr double kMaxStartOverlap = 0.5;
// Centres closer than this share of the smaller radius count as the same position.
inline constexpr double kCoincidentCentres = 1e-9;

// UsageError naming the file, the frame and the pair if two grains have coincident
// centres or overlap by more than kMaxStartOverlap of the smaller radius (minimum images in
// the box; a cell list, O(N)). Positions need not be wrapped.
void check_start_grains(const std::string& path, std::size_t frame, const Box& box, const std::vector<Vec2>& position,
                        const std::vector<double>& radius);

// UsageError naming the file, the frame and the contact unless the contacts can warm-start
// the engine: pairs i < j in strictly increasing (i, j) order, ages >= 1 (the values
// themselves are checked by the reader).
void check_start_contacts(const std::string& path, std::size_t frame, const io::ContactRecords& contacts);

// UsageError naming the file if it was written by gf-shear or gf-incline (its /parameters
// program) but has no /contacts: its frames then lack the warm start that makes them exact
// restart points. Packings (gf-pack) and files of other origin need no contacts.
void require_run_contacts(const io::TrajectoryReader& input);

}  // namespace granflow
