# The tolerance study at μ = 0.4 (make -f Makefile.sweeps friction-tolerance; rules in
# pipelines/friction_tolerance.mk, results in docs/results/convergence.md, "The tolerance at
# μ = 0.4"). Another grid: make -f Makefile.sweeps friction-tolerance FRICTION_TOLERANCE=path/to/grid.mk.
#
# One run per ν of FT_NU, seed of FT_SEEDS (one gf-pack packing each) and solver tolerance of
# FT_TOLERANCES (gf-shear --tolerance: residual velocity × dt, Υ = tolerance/dt), all at N = FT_GRAINS,
# e = FT_RESTITUTION, μ = FT_FRICTION, strain step FT_STEP; each looser tolerance is compared with
# FT_DEFAULT_TOLERANCE (one of FT_TOLERANCES, at least two).
FT_GRAINS            := 1000
FT_NU                := 0.760 0.780
FT_RESTITUTION       := 0.00
FT_FRICTION          := 0.40
FT_SEEDS             := 1 2
FT_TOLERANCES        := 1e-10 1e-9 1e-8
FT_DEFAULT_TOLERANCE := 1e-10
FT_STEP              := 1e-3
# The convergence study's observation settings: FT_STRAIN strain units at γ̇ = FT_RATE, an
# observable row every FT_OBSERVE_STRAIN and a frame every FT_FRAME_STRAIN of strain, averages from
# FT_FROM_STRAIN (later where the run's own transient ends).
FT_STRAIN            := 20
FT_RATE              := 1
FT_FROM_STRAIN       := 1
FT_OBSERVE_STRAIN    := 2e-3
FT_FRAME_STRAIN      := 4e-2
# A force-bearing contact slides when |F_t| >= (1 - FT_SLIDING_MARGIN)·μF_n (sliding_share.py).
FT_SLIDING_MARGIN    := 1e-6
# An observable "moves" when a looser tolerance differs from the default by more than FT_SIGMAS
# combined errors at any ν and seed.
FT_SIGMAS            := 2
