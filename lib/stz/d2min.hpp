#pragma once
// Falk–Langer non-affine displacement D²min (thesis eq. 6.32) between two frames of a
// sheared periodic (Lees–Edwards) box. docs/method/stz.md says what is computed and why.
//
// Neighbours are taken in the reference frame. A bond is never minimum-imaged at the later
// time: the reference bond d⁰ goes to the image of the neighbour in image row k (k Ly shifts,
// x shifted by k·offset), and the current bond follows that same image,
//   d = d⁰ + u_n − u_0 + k·Δδ x̂,
// with u the unwrapped displacement of each grain and Δδ the accumulated (not wrapped)
// change of the Lees–Edwards offset. A wrapped offset, strains above 1 and γ̇ < 0 are
// then harmless.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/vec.hpp"
#include "geometry/box.hpp"

namespace granflow::stz {

// Y = Σ d⁰d⁰ᵀ counts as singular when its smaller eigenvalue is below this fraction of its
// larger (condition number above 10⁸): collinear neighbours give round-off there, and every
// neighbourhood above it leaves F at least half of double precision's digits.
inline constexpr double kSingularRatio = 1e-8;

// The bonds of the reference frame, per grain (CSR: grain i's bonds are
// [start[i], start[i+1])): neighbour index, image row k of the neighbour, d⁰ = r_n − r_i.
struct ReferenceBonds {
  std::vector<std::int64_t> start;
  std::vector<std::int32_t> neighbour;
  std::vector<std::int32_t> row;
  std::vector<Vec2> bond;
};

// Every pair closer than cutoff (centre distance, strict) by the Lees–Edwards minimum image
// of `box`, found with a cell list in O(N); both directions stored. positions must lie in
// the primary cell [0, lx) × [0, ly) (as stored by gf-shear), the box must be periodic in y,
// and 0 < cutoff < min(lx, ly)/2 (so that no two images of a grain are both in range).
// Throws std::invalid_argument otherwise.
ReferenceBonds reference_bonds(const std::vector<Vec2>& positions, const Box& box, double cutoff);

struct D2min {
  std::vector<double> value;          // Σ_n |d_n − F d⁰_n|² (Falk–Langer, OVITO); NaN if invalid
  std::vector<double> per_neighbour;  // value / neighbours; NaN if invalid
  std::vector<std::int32_t> neighbours;
  std::vector<std::uint8_t> valid;  // 0: fewer than 2 neighbours or Y singular
  std::vector<Mat2> F;              // best local affine map (X Y⁻¹); NaN if invalid
};

// D²min of every grain. reference: wrapped positions of the reference frame, its box;
// displacement: unwrapped displacement of every grain from the reference to the current
// frame; offset_change: accumulated change Δδ of the Lees–Edwards offset between them.
// Throws std::invalid_argument for ragged or non-finite input (and as reference_bonds).
D2min compute_d2min(const std::vector<Vec2>& reference, const Box& box, const std::vector<Vec2>& displacement,
                    double offset_change, double cutoff);
// Same on bonds already found (one neighbour search, several current frames).
D2min compute_d2min(const ReferenceBonds& bonds, const std::vector<Vec2>& displacement, double offset_change);

// One stored frame: wrapped positions (Box::wrap), its box (the wrapped offset), its time.
struct StoredFrame {
  std::span<const Vec2> position;
  Box box;
  double time = 0;
};

struct Unwrapped {
  std::vector<Vec2> displacement;  // from the first frame to the last, per grain
  double offset_change = 0;        // Δδ between them, not wrapped
};

// Unwrapped displacements across a sequence of stored frames of one run (or of a run and a
// branch started from its first frame), image counters carried from frame to frame: a grain
// that leaves through the top re-enters shifted by −offset, and its image keeps moving with
// the offset afterwards. rate: the shear rate γ̇ in the frames' time unit. Δδ is
// rate·ly·(t_last − t_first), taken as the value of that size congruent to the stored
// offsets modulo lx. Throws std::invalid_argument naming the frame and grain when the frames
// are ragged, their boxes differ in size or are not periodic in y, times decrease, a stored
// offset disagrees with the rate (by more than 10⁻⁶ lx), or a grain moves, between two
// consecutive frames, by at least half of min(lx, ly) (its image would be ambiguous; a
// jump that aliases to a shorter one cannot be seen: store frames often enough).
Unwrapped unwrap_displacements(std::span<const StoredFrame> frames, double rate);

// The same, one frame at a time, so that a long sequence of frames is read and unwrapped in
// memory O(N) (gf-stz d2min reads every stored frame between the two it compares). Each
// frame is checked against the first and the previous one as above, and is named in the
// messages by `name` (e.g. "'run.h5' frame 12"). The frame's positions are copied: the
// caller may reuse their storage.
class Unwrapper {
 public:
  Unwrapper(const StoredFrame& first, double rate, std::string name = "frame 0");
  void add(const StoredFrame& frame, std::string name);
  // Displacements from the first frame to the last one added, and Δδ between them.
  Unwrapped result() const;
  std::size_t frames() const { return frames_; }

 private:
  std::vector<Vec2> first_, unwrapped_;
  Box first_box_, last_box_;
  double rate_ = 0, first_time_ = 0, last_time_ = 0;
  std::string last_name_;
  std::size_t frames_ = 1;
};

}  // namespace granflow::stz
