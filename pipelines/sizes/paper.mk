# The thesis' sizes (chapter 4: N = 10^4 grains in simple shear).
PACK_GRAINS := 10000
PACK_NU     := 0.400 0.500 0.600 0.650 0.700 0.720 0.740 0.760 0.770 0.780 0.790 0.800 0.810 0.820
PACK_SEEDS  := 1
# Chapter 4, simple shear: the thesis' ν range (Fig 4.5 shows the static/kinetic crossover
# at ν ≈ 0.4, so the grid starts below it; dense steps of 0.01 up to 0.83 < ν_max = 0.84),
# restitutions 0, 0.25, 0.5, 0.75, 0.92; Fig 4.2 at ν = 0.8 with γ̇ = 1e-2 and 1e2.
CH4_NU            := 0.100 0.200 0.300 $(PACK_NU) 0.830
CH4_E             := 0.00 0.10 0.25 0.50 0.75 0.92
CH4_RATE          := 1e-02
CH4_BAGNOLD_NU    := 0.800
CH4_BAGNOLD_RATES := 1e-02 1e+02
CH4_SEED          := 1
CH4_FROM_STRAIN   := 0.5
SHEAR_STRAIN      := 20
SHEAR_STRAIN_STEP := 1e-3
# Frames every 100 steps: ~195 frames past strain 0.5 for chapter 5 (the thesis averages
# C(l) over >= 5000 steps; frames 100 steps apart are nearly independent samples).
SHEAR_FRAME_EVERY := 100
# Dilute flows sheared from rest heat up for many strain units (measured at N = 1000: T
# steady only from strain ~40 at ν = 0.1, ~35 at 0.2, ~15 at 0.3 and 0.4 for e = 0; ~28,
# 20, 14 for e = 0.92): runs at ν <= 0.7 go on to strain 80, frames 4 times sparser; the
# analyses find where each run's steady part starts (MSER, at most half of the run).
SHEAR_LONG_NU          := 0.100 0.200 0.300 0.400 0.500 0.600 0.650 0.700
SHEAR_LONG_STRAIN      := 80
SHEAR_LONG_FRAME_EVERY := 400
# Chapter 5: the chapter-4 ν grid (dense steps of 0.01 as in the Fig 5.3 inset), every e
# at μ = 0; Fig 5.4 at e = 0 for three μ (the thesis names three friction coefficients
# without their values: 0, 0.1 and 0.4 here, 0.4 being the thesis' frictional case), up to
# ν = 0.80 (frictional flows jam earlier; Fig 4.10 stops there too).
CH5_NU            := $(CH4_NU)
CH5_E             := 0.00 0.10 0.25 0.50 0.75 0.92
CH5_MU            := 0.00 0.10 0.40
CH5_FRICTION_E    := 0.00
CH5_FRICTION_NU   := $(filter-out 0.810 0.820 0.830,$(CH5_NU))
CH5_RATE          := $(CH4_RATE)
CH5_SEED          := $(CH4_SEED)
CH5_FROM_STRAIN   := 0.5
CH5_REFERENCE_NU  := 0.100
CH5_REFERENCE_E   := 0.92
CH5_CLUSTER_NU    := 0.790
CH5_CLUSTER_E     := 0.92 0.00
CH5_WINDOW_STEPS  := 2
# ν_c(μ, e) from the divergence of p/γ̇² and s/γ̇² (jamming_point.py): the runs at ν >= this;
# a (μ, e) group with fewer than 4 of them is listed, not fitted.
CH5_JAMMING_FROM_NU := 0.700
# Shear runs at μ = 0.4 for Fig 4.10 (right), around the incline's bulk ν.
CH4_FRICTION_NU   := 0.700 0.740 0.760 0.770 0.780 0.790 0.800
CH4_FRICTION_E    := 0.50
CH4_INCLINE_NU    :=
# Chapter 6, kinetic theory (gf-kinetic): the μ = 0 runs of the chapter-4 grid at CH4_RATE, and
# elastic (e = 1) unsheared runs at every ν of that grid for χ (packings at ν outside PACK_NU are
# made by the same rule). The quick size's recipe (ch6_recipe.mk), NOT measured at N = 10⁴:
# a ν it has no steps for takes those of the nearest denser ν measured (a smaller step is safe,
# only slower); check each run's energy drift (gf-kinetic's /equilibrium/energy_drift).
CH6_EQ_NU            := $(CH4_NU)
CH6_EQ_SEED          := $(CH4_SEED)
include pipelines/sizes/ch6_recipe.mk
CH6_EQ_WARMUP_DT_0.100 := $(CH6_EQ_WARMUP_DT_0.200)
CH6_EQ_DT_0.100        := $(CH6_EQ_DT_0.200)
CH6_EQ_WARMUP_DT_0.650 := $(CH6_EQ_WARMUP_DT_0.700)
CH6_EQ_DT_0.650        := $(CH6_EQ_DT_0.700)
$(foreach nu,0.720 0.740,$(eval CH6_EQ_WARMUP_DT_$(nu) := $(CH6_EQ_WARMUP_DT_0.760))$(eval CH6_EQ_DT_$(nu) := $(CH6_EQ_DT_0.760)))
$(foreach nu,0.770 0.780 0.790,$(eval CH6_EQ_WARMUP_DT_$(nu) := $(CH6_EQ_WARMUP_DT_0.800))$(eval CH6_EQ_DT_$(nu) := $(CH6_EQ_DT_0.800)))
CH6_EQ_WARMUP_DT_0.810 := $(CH6_EQ_WARMUP_DT_0.820)
CH6_EQ_DT_0.810        := $(CH6_EQ_DT_0.820)
CH6_FROM_STRAIN      := $(CH4_FROM_STRAIN)
# Chapter 6, force-network model (gf-network): Fig. 6.7's inset, z at the default step and at half
# of it, from half-step runs (the shear run of the same name at SHEAR_STRAIN_STEP/2, twice its cost)
# at these ν, e.
CH6_HALFSTEP_NU      := 0.700 0.790 0.810 0.820
CH6_HALFSTEP_E       := 0.00 0.50 0.92
# Chapter 4, incline: the thesis' sizes are "heights and widths ranging between 25 and 300
# grain diameters" (§4.3.1); here a layer 50 diameters thick on a base 100 wide (~5·10³
# grains), the default step 2e-3 τ, 2000 τ per run (the transient grows with the height:
# ~200 τ at 25 diameters), the steady part detected (MSER). SIZE=paper INCLINE_HEIGHT=300
# INCLINE_WIDTH=300 makes the largest of the thesis (~9·10⁴ grains).
INCLINE_WIDTH           := 100
INCLINE_HEIGHT          := 50
INCLINE_SEED            := 1
INCLINE_E               := 0.50
INCLINE_REFERENCE_ANGLE := 12
INCLINE_ANGLES_MU0      := 9 10 11 12 13 14 15
INCLINE_ANGLES_MU04     := 18 20 22 24 26
# μ = 0.4 branched from the end of the steepest μ = 0 run (15°, a dense flowing layer) instead
# of the dilute start, whose frictional collapse costs 818-2251 sweeps per step; 1000 τ at the
# same step, the steady part detected. Not run at this size: the dense frictional flow costs
# ~10³ sweeps per step at 10³ grains (quick size), more in a thicker layer.
INCLINE_MU04_PARENT     := 15
INCLINE_BRANCH_TIME     := 1000
INCLINE_BRANCH_TIME_STEP := 2e-3
INCLINE_BRANCH_FROM_TIME :=
INCLINE_BRANCH_TOLERANCE :=
INCLINE_CRITICAL_ANGLES := 4 5 6 7 8
INCLINE_TIME            := 2000
INCLINE_TIME_STEP       := 2e-3
INCLINE_FROM_TIME       :=
INCLINE_PROFILE_BLOCK   := 5000
INCLINE_FRAME_EVERY     := 50000
INCLINE_CRITICAL_WINDOW := 300
INCLINE_BASE_SKIP       := 3
INCLINE_SURFACE_SKIP    := 8
# Chapter 6, STZ (gf-stz): Fig. 6.9 from the last frame of the ν = 0.80, e = 0, μ = 0 run (N = 10⁴,
# as the thesis' pictures), frames every strain 0.005; the fit over the chapter-5 grids, dense
# by ξ/ξ_el ≥ 1.25; e = 0 incline points at three angles per μ, the μ = 0.4 ones branched from
# the 14° μ = 0 run (not run at this size yet: the angles follow the quick size's flowing range).
CH6_STZ_NU          := 0.800
CH6_STZ_E           := 0.00
CH6_STZ_INTERVAL    := 0.05
CH6_STZ_FORWARD     := 0.15
CH6_STZ_FRAME_EVERY := 5
CH6_STZ_CUTOFF      := 2
CH6_INCLINE_E           := 0.00
CH6_INCLINE_ANGLES_MU0  := 10 12 14
CH6_INCLINE_ANGLES_MU04 := 20 21 22
CH6_INCLINE_MU04_PARENT := 14
