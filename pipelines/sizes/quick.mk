# Quick reproduction (the default SIZE): 1000 grains per run; the shear runs' budget is below.
PACK_GRAINS := 1000
PACK_NU     := 0.300 0.400 0.500 0.600 0.700 0.760 0.800 0.820
PACK_SEEDS  := 1
# Chapter 4, simple shear (gf-shear): the ν grid of Figs 4.4-4.6 at CH4_RATE for every
# restitution of Fig 4.6 (e = 0 serves Figs 4.4, 4.5), and the Bagnold pair of Fig 4.2
# (ν = CH4_BAGNOLD_NU, e = 0, two rates, same packing); ν from 0.3 so that Fig 4.5 shows
# the static/kinetic crossover. Budget: in a fresh-clone `make -j2` the 79 shear
# runs of chapters 4 and 5 (those at SHEAR_LONG_NU 40 strain units long) all finished within
# 9 min of wall time; SHEAR_STRAIN is the knob (make SHEAR_STRAIN=3 ...).
CH4_NU            := $(PACK_NU)
CH4_E             := 0.00 0.10 0.25 0.50 0.75 0.92
CH4_RATE          := 1e-02
CH4_BAGNOLD_NU    := 0.800
CH4_BAGNOLD_RATES := 1e-02 1e+02
CH4_SEED          := 1
CH4_FROM_STRAIN   := 0.5
SHEAR_STRAIN      := 5
SHEAR_STRAIN_STEP := 1e-3
# Frames every 20 steps (strain 0.02): chapter 5 averages C(l) and P(f) over the stored
# frames of the same runs (225 frames past strain 0.5; the thesis: >= 5000 steps).
SHEAR_FRAME_EVERY := 20
# Dilute flows sheared from rest heat up for many strain units: T still rises at strain 5
# for ν <= 0.6 (N = 1000, every e; at ν = 0.3 until strain ~15, at 0.5 until ~6, at 0.6
# until ~2.5 for e = 0.92), and ν = 0.7 drifts over several units. Runs at these ν go on
# to strain 40 (a few seconds each: few contacts), frames 8 times sparser (the same 250);
# the analyses find where each run's steady part starts (MSER, at most half of the run).
SHEAR_LONG_NU          := 0.300 0.400 0.500 0.600 0.700
SHEAR_LONG_STRAIN      := 40
SHEAR_LONG_FRAME_EVERY := 160
# Chapter 5 (gf-correlate): the same runs where the grids agree. N = 1000 (half side ≈ 15σ
# at ν = 0.8, the largest lag counted) keeps ξ measurable up to ν ≈ 0.8; the ν grid adds
# the dilute end and the dense steps of Figs 5.2-5.3 (ν_c ≈ 0.845). Figs 5.3, 5.5-5.10 for
# every e at μ = 0; Fig 5.4 at e = CH5_FRICTION_E for every μ over CH5_FRICTION_NU (frictional
# runs cost more, growing towards their lower jamming point, ν_c ≈ 0.805 at μ = 0.4: 17 s of CPU
# at ν = 0.78, 46 sweeps per step, 38 s at 0.79, 107 sweeps; docs/performance.md, "Frictional
# flows"; 0.79 is there for the fit of ν_c). ξ_el from the dilute run(s)
# at CH5_REFERENCE_NU, e = CH5_REFERENCE_E. Fig 5.1: a CH5_WINDOW_STEPS-step branch
# (--frame-every 1) from the end of the runs at CH5_CLUSTER_NU for each CH5_CLUSTER_E.
CH5_NU            := 0.300 0.500 0.600 0.700 0.740 0.760 0.770 0.780 0.790 0.800 0.810 0.820
CH5_E             := 0.00 0.10 0.25 0.50 0.75 0.92
CH5_MU            := 0.00 0.40
CH5_FRICTION_E    := 0.00
CH5_FRICTION_NU   := 0.300 0.500 0.600 0.700 0.740 0.760 0.770 0.780 0.790
CH5_RATE          := $(CH4_RATE)
CH5_SEED          := $(CH4_SEED)
CH5_FROM_STRAIN   := 0.5
CH5_REFERENCE_NU  := 0.300
CH5_REFERENCE_E   := 0.92
CH5_CLUSTER_NU    := 0.790
CH5_CLUSTER_E     := 0.92 0.00
CH5_WINDOW_STEPS  := 2
# ν_c(μ, e) from the divergence of p/γ̇² and s/γ̇² (jamming_point.py): the runs at ν >= this;
# a (μ, e) group with fewer than 4 of them is listed, not fitted.
CH5_JAMMING_FROM_NU := 0.700
# Shear runs at μ = 0.4 for Fig 4.10 (right), around the incline's bulk ν (friction lowers it:
# 0.785-0.790 at 19-21°; 0.790 brackets 20° and 21° and is 19°'s own ν within its ±0.002).
# Cost grows fast: 0.780 32 sweeps per step, 0.790 61 (20 s of CPU), 0.800 535 (105 s; 0.006
# below ν_c at μ = 0.4; 2 of its 5000 steps at the frictional sweep cap of 10^5, where the cap
# of 10^4 stopped the run at 1 %: docs/performance.md, "Frictional flows").
CH4_FRICTION_NU   := 0.700 0.760 0.780 0.790 0.800
CH4_FRICTION_E    := 0.50
# μ = 0 shear runs at e = CH4_FRICTION_E bracketing the incline's bulk ν (0.81-0.83 at 10-14°).
CH4_INCLINE_NU    := 0.810 0.825
# Chapter 6, kinetic theory (gf-kinetic): the μ = 0 runs of the chapter-4 grid at CH4_RATE, and
# elastic (e = 1) unsheared runs at every ν of that grid for χ (from its packing; CH6_EQ_NU must
# cover the sheared runs' ν: gf-kinetic does not extrapolate without --extrapolate), made by
# the recipe measured on these packings (ch6_recipe.mk).
CH6_EQ_NU            := $(CH4_NU)
CH6_EQ_SEED          := $(CH4_SEED)
include pipelines/sizes/ch6_recipe.mk
CH6_FROM_STRAIN      := $(CH4_FROM_STRAIN)
# Chapter 6, force-network model (gf-network): Fig. 6.7's inset, z at the default step and at half
# of it, from half-step runs (the shear run of the same name at SHEAR_STRAIN_STEP/2) at these ν, e.
# Cost: 3-21 s each, 65 s for the six (wall time, one core of a loaded machine), 1.6 times the
# default-step run of the same name at ν = 0.70 and 0.81, e = 0.
CH6_HALFSTEP_NU      := 0.700 0.790 0.810
CH6_HALFSTEP_E       := 0.00 0.50
# Chapter 4, incline (gf-incline): a layer 25 diameters thick on a base 40 wide (~1000
# grains), e = 0.5; Figs 4.7-4.9 at 12°, μ = 0. Cost: docs/performance.md, gf-incline.
INCLINE_WIDTH           := 40
INCLINE_HEIGHT          := 25
INCLINE_SEED            := 1
INCLINE_E               := 0.50
INCLINE_REFERENCE_ANGLE := 12
INCLINE_ANGLES_MU0      := 10 12 14
# μ = 0.4 incline runs (Fig 4.10 right) branch from the last frame (400 τ) of the 14° μ = 0 run:
# a dense layer already flowing at about the speed a μ = 0.4 layer keeps at 19-21°. From
# gf-pack's dilute start the frictional collapse cost 818-2251 sweeps per step (~1 CPU hour
# per 400 τ run); the branch skips the collapse and the slow acceleration, the layer dilates
# to its frictional ν within ~5 τ, then relaxes from the parent's faster flow for ~100 τ. With
# the frictional cluster solves the flow needs 43-84 sweeps per step (Gauss-Seidel alone
# ~1000), so the runs go on to 400 τ at 5e-3 τ, averaged from 200 τ, where the flow rate of
# the two halves of the window agrees within ~2 %: 130-420 s of CPU each (docs/performance.md,
# "Frictional flows").
INCLINE_ANGLES_MU04     := 19 20 21
INCLINE_MU04_PARENT     := 14
INCLINE_BRANCH_TIME     := 400
INCLINE_BRANCH_TIME_STEP := 5e-3
INCLINE_BRANCH_FROM_TIME := 200
INCLINE_BRANCH_TOLERANCE :=
INCLINE_CRITICAL_ANGLES := 5 7
INCLINE_TIME            := 400
INCLINE_TIME_STEP       := 5e-3
INCLINE_FROM_TIME       := 200
INCLINE_PROFILE_BLOCK   := 2000
INCLINE_FRAME_EVERY     := 10000
INCLINE_CRITICAL_WINDOW := 200
INCLINE_BASE_SKIP       := 3
INCLINE_SURFACE_SKIP    := 8
# Chapter 6, STZ (gf-stz). Fig. 6.9: D²min maps from the last frame (strain 5) of the ν = 0.80,
# e = 0, μ = 0 run of the chapter-5 grid: dense (the thesis' STZ regime) yet below jamming
# (ν_c ≈ 0.845), so it flows steadily; μ = 0 keeps the branches cheap, and e = 0 is the
# restitution the law is fitted on. Branches at γ̇dt = SHEAR_STRAIN_STEP with a frame every 5
# steps (strain 0.005): forward to strain 0.15 (maps a, b, c), backward to −0.05 (map d).
CH6_STZ_NU          := 0.800
CH6_STZ_E           := 0.00
CH6_STZ_INTERVAL    := 0.05
CH6_STZ_FORWARD     := 0.15
CH6_STZ_FRAME_EVERY := 5
CH6_STZ_CUTOFF      := 2
# The fit: the chapter-5 grids (μ = 0: CH5_NU × CH5_E; μ = 0.4: CH5_FRICTION_NU at e = 0), dense by
# ξ/ξ_el ≥ 1.25 from the chapter-5 table. Incline points (never fitted) at e = 0: μ = 0 at two
# angles, μ = 0.4 at two angles branched from the 14° μ = 0 run (as few as carry the comparison;
# the chapter-4 incline settings above). Cost: docs/results/chapter6.md, STZ.
CH6_INCLINE_E           := 0.00
CH6_INCLINE_ANGLES_MU0  := 12 14
CH6_INCLINE_ANGLES_MU04 := 20 21
CH6_INCLINE_MU04_PARENT := 14
