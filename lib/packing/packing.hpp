#pragma once
// Initial configurations (thesis App. A.3): biperiodic packings at a prescribed
// packing fraction for simple shear, and a dilute layer above a fixed rough base
// for incline flow. Physics only: the tools do the I/O.
//
// Grain sizes (thesis Ch. 4): diameters uniform in [σ−Δ, σ+Δ], with σ the mean
// diameter and Δ/σ the polydispersity (σ = 1.4, Δ = 0.26σ by default).
#include <cstdint>
#include <functional>
#include <vector>

#include "core/random.hpp"
#include "core/vec.hpp"
#include "geometry/box.hpp"

namespace granflow {

struct PackingParams {
  std::int64_t grains = 0;
  double packing_fraction = 0;
  double mean_diameter = 1.4;
  double polydispersity = 0.26;  // Δ/σ
  std::uint64_t seed = 1;
  double overlap_tolerance = 1e-9;  // target max overlap, in units of σ
};

struct InclineParams {
  double width = 0;         // base length, in mean diameters
  double height = 0;        // layer thickness, in mean diameters (used when grains == 0)
  std::int64_t grains = 0;  // mobile grains; 0: derived from height
  double mean_diameter = 1.4;
  double polydispersity = 0.26;
  std::uint64_t seed = 1;
};

struct Packing {
  Box box;
  std::vector<Vec2> position;  // wrapped into the box (x in [0, lx); y in [0, ly) if periodic)
  std::vector<double> radius;
  std::vector<std::uint8_t> fixed;  // 1: immobile base grain (incline)
  // Biperiodic: Σπr²/(lx·ly). Incline: mobile grains' area over lx × (height of the
  // layer between the base top and the highest grain top).
  double packing_fraction = 0;
  double max_overlap = 0;       // max over pairs of R_i + R_j − |x_i − x_j| (absolute length), ≥ 0
  std::int64_t iterations = 0;  // minimiser steps
  double seconds = 0;           // wall time
};

// Throw UsageError naming the option as the command line spells it.
void validate(const PackingParams& p);
void validate(const InclineParams& p);

// n radii with diameters uniform in [σ−Δ, σ+Δ), σ = mean_diameter, Δ = polydispersity·σ.
std::vector<double> draw_radii(std::int64_t n, double mean_diameter, double polydispersity, Rng& rng);

// Largest pairwise overlap in the box (0 if no two grains overlap), by cell lists.
double max_overlap(const Box& box, const std::vector<Vec2>& position, const std::vector<double>& radius);

// Square biperiodic box (Lees–Edwards offset 0) at exactly the requested packing
// fraction: all radii grow by a common factor from a dilute random start while a
// harmonic soft repulsion is minimised (FIRE), then the packing is relaxed at full
// size until the max overlap is below overlap_tolerance·σ or the energy stops
// decreasing (jammed: ν above ≈ 0.84, the residual is reported in max_overlap).
// progress(fraction_done, current max overlap in units of σ) is called now and then.
// Same params → bit-identical positions and radii. Throws UsageError, Interrupted.
Packing make_biperiodic_packing(const PackingParams& p,
                                const std::function<void(double fraction_done, double max_overlap)>& progress = {});

// The grains of an existing biperiodic packing (or trajectory frame) at another
// packing fraction: radii kept, box and positions scaled (same shape, ν exact,
// Lees–Edwards offset dropped), then grown/relaxed as above until the max overlap is
// below overlap_tolerance·σ (σ = the grains' mean diameter). UsageError for a box
// open in y or fixed grains.
Packing repack(const Packing& start, double packing_fraction, double overlap_tolerance,
               const std::function<void(double fraction_done, double max_overlap)>& progress = {});

// K × K copies of a biperiodic packing or sheared frame in a box K times wider and taller,
// at the same packing fraction: copy (a, b) is the cell moved by a·(Lx, 0) + b·(δ, Ly), the
// cell's own periodic image, so copies meet as the cell meets its images and every pair of
// grains within reach has the same separation as in the cell; the large box's Lees–Edwards
// offset is K·δ (wrapped). Grains are numbered band by band, as make_biperiodic_packing()
// numbers them; max_overlap is the cell's. A start for large N at a cost linear in N: a
// gf-pack packing of N grains touches everywhere, and gf-shear's first steps from it solve
// one cluster spanning the box, a cost that grows as N^1.5 or faster. UsageError for K < 1,
// a box open in y, fixed grains, or more than 2³¹ − 1 grains.
Packing tile(const Packing& cell, long long copies);

// Incline start: a row of touching fixed grains centred on y = 0 that closes on
// itself through the periodic x boundary, and mobile grains on a jittered lattice
// above it, none overlapping. Base grains come first. Box open in y.
Packing make_incline_packing(const InclineParams& p);

}  // namespace granflow
