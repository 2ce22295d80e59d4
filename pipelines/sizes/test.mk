# Tiny sweep for the pipeline tests: seconds.
PACK_GRAINS := 64
PACK_NU     := 0.500 0.700
PACK_SEEDS  := 1 2
# Chapter 4: two ν, two e and the Bagnold pair; strain 0.2 (200 steps), steady from 0.05.
CH4_NU            := $(PACK_NU)
CH4_E             := 0.00 0.92
CH4_RATE          := 1e-02
CH4_BAGNOLD_NU    := 0.700
CH4_BAGNOLD_RATES := 1e-02 1e+02
CH4_SEED          := 1
CH4_FROM_STRAIN   := 0.05
SHEAR_STRAIN      := 0.2
SHEAR_STRAIN_STEP := 1e-3
SHEAR_FRAME_EVERY := 10
# Longer runs at ν = 0.5 (see quick.mk): exercises the per-ν strain.
SHEAR_LONG_NU          := 0.500
SHEAR_LONG_STRAIN      := 0.3
SHEAR_LONG_FRAME_EVERY := 15
# Chapter 5: the chapter-4 runs plus μ = 0.4 at e = 0; ξ_el from ν = 0.5, e = 0.92;
# a 10-step cluster window at ν = 0.7 (with 2, 64 grains at e = 0.92 can have no contact in any frame).
CH5_NU            := $(PACK_NU)
CH5_E             := $(CH4_E)
CH5_MU            := 0.00 0.40
CH5_FRICTION_E    := 0.00
CH5_FRICTION_NU   := $(CH5_NU)
CH5_RATE          := $(CH4_RATE)
CH5_SEED          := $(CH4_SEED)
CH5_FROM_STRAIN   := $(CH4_FROM_STRAIN)
CH5_REFERENCE_NU  := 0.500
CH5_REFERENCE_E   := 0.92
CH5_CLUSTER_NU    := 0.700
CH5_CLUSTER_E     := 0.92 0.00
CH5_WINDOW_STEPS  := 10
# ν_c(μ, e) from the divergence of p/γ̇² and s/γ̇² (jamming_point.py): the runs at ν >= this;
# a (μ, e) group with fewer than 4 of them is listed, not fitted.
CH5_JAMMING_FROM_NU := 0.700
CH4_FRICTION_NU   := 0.700
CH4_FRICTION_E    := 0.50
CH4_INCLINE_NU    :=
# Chapter 6: the μ = 0 runs of the chapter-4 grid (2 ν, 2 e) and a very short elastic run at
# each ν (a 20-step warm-up, 20 settling steps, 100 measured steps), only to exercise the rules.
CH6_EQ_NU            := $(CH4_NU)
CH6_EQ_SEED          := $(CH4_SEED)
CH6_EQ_WARMUP_DT     := 1e-3
CH6_EQ_DT            := 1e-3
CH6_EQ_WARMUP_STEPS  := 20
CH6_EQ_SETTLE_STEPS  := 20
CH6_EQ_STEPS         := 100
CH6_EQ_FRAME_EVERY   := 20
CH6_EQ_OBSERVE_EVERY := 1
CH6_FROM_STRAIN      := $(CH4_FROM_STRAIN)
# Chapter 6, force-network model: one half-step run (the ν = 0.7, e = 0 run at half the step),
# only to exercise the rule and the second table.
CH6_HALFSTEP_NU      := 0.700
CH6_HALFSTEP_E       := 0.00
# 64 grains: the reference run's ξ_el is not finite, and gf-network refuses a correlation table
# without ξ_el; the force-network table is made without one (no right-hand sides). Only the
# ν = 0.7, e = 0 run has long-lived contacts (age ≥ 2) in its window (the others: none in most
# or all frames), and gf-network refuses a run without any.
CH6_NETWORK_CORRELATION :=
CH6_NETWORK_NU       := 0.700
CH6_NETWORK_E        := 0.00
# Chapter 4, incline: a layer 12 diameters thick on a base 10 wide, 20 τ (the bulk table needs
# a few layers of 3 diameters between the skipped base and surface).
INCLINE_WIDTH           := 10
INCLINE_HEIGHT          := 12
INCLINE_SEED            := 1
INCLINE_E               := 0.50
INCLINE_REFERENCE_ANGLE := 20
INCLINE_ANGLES_MU0      := 20
INCLINE_ANGLES_MU04     := 30
# μ = 0.4 branched from the end of the 20° μ = 0 run, 10 τ averaged from 2 τ.
INCLINE_MU04_PARENT     := 20
INCLINE_BRANCH_TIME     := 10
INCLINE_BRANCH_TIME_STEP := 5e-3
INCLINE_BRANCH_FROM_TIME := 2
INCLINE_BRANCH_TOLERANCE :=
INCLINE_CRITICAL_ANGLES := 5
INCLINE_TIME            := 20
INCLINE_TIME_STEP       := 5e-3
INCLINE_FROM_TIME       := 5
INCLINE_PROFILE_BLOCK   := 200
INCLINE_FRAME_EVERY     := 1000
INCLINE_CRITICAL_WINDOW := 10
INCLINE_BASE_SKIP       := 1
INCLINE_SURFACE_SKIP    := 1
# Chapter 6, STZ: maps from the ν = 0.7, e = 0 run (64 grains), the thesis' strains (150 steps),
# a frame every 10 steps. The fit: 64-grain runs of strain 0.2 are noisy, and three points per μ
# gave a μ(I) fit that does not converge; these grids (5 ν at μ = 0 for e = 0 and 0.92, 4 at
# μ = 0.4) are ones whose STZ and μ(I) fits converge (their coefficients mean nothing), all
# counted dense (ν ≥ 0.55, below the smallest ν: a 0.600 packing is 0.5999…; no correlation
# table: ξ_el is not finite at 64 grains). μ = 0.4 stops at ν = 0.76: at 0.78 the 64-grain run
# exceeds --max-unconverged. One e = 0 incline run per μ (the μ = 0.4 one branched from the
# μ = 0 one), only to exercise the rules.
CH6_STZ_NU          := 0.700
CH6_STZ_E           := 0.00
CH6_STZ_INTERVAL    := 0.05
CH6_STZ_FORWARD     := 0.15
CH6_STZ_FRAME_EVERY := 10
CH6_STZ_CUTOFF      := 2
CH6_STZ_FIT_NU      := 0.700 0.740 0.760 0.780 0.800
CH6_STZ_FIT_E       := $(CH4_E)
CH6_STZ_FRICTION_NU := 0.600 0.700 0.740 0.760
CH6_STZ_CORRELATION :=
CH6_STZ_MIN_NU      := 0.55
CH6_INCLINE_E           := 0.00
CH6_INCLINE_ANGLES_MU0  := 20
CH6_INCLINE_ANGLES_MU04 := 30
CH6_INCLINE_MU04_PARENT := 20
