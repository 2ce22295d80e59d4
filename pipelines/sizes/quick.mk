# Quick reproduction: minutes on a laptop.
PACK_GRAINS := 1000
PACK_NU     := 0.600 0.700 0.760 0.800 0.820
PACK_SEEDS  := 1
# Chapter 4, simple shear (gf-shear): the ν grid of Figs 4.4-4.6 at CH4_RATE for every
# restitution of Fig 4.6 (e = 0 serves Figs 4.4, 4.5), and the Bagnold pair of Fig 4.2
# (ν = CH4_BAGNOLD_NU, e = 0, two rates, same packing). Budget: the 26 runs in < 10 min
# with -j2; SHEAR_STRAIN is the knob (make SHEAR_STRAIN=3 ...).
CH4_NU            := $(PACK_NU)
CH4_E             := 0.00 0.25 0.50 0.75 0.92
CH4_RATE          := 1e-02
CH4_BAGNOLD_NU    := 0.800
CH4_BAGNOLD_RATES := 1e-02 1e+02
CH4_SEED          := 1
CH4_FROM_STRAIN   := 0.5
SHEAR_STRAIN      := 5
SHEAR_STRAIN_STEP := 1e-3
SHEAR_FRAME_EVERY := 1000
# Shear runs at μ = 0.4 for Fig 4.10 (right), around the incline's bulk ν (friction lowers it).
CH4_FRICTION_NU   := 0.700 0.760 0.780
CH4_FRICTION_E    := 0.50
# μ = 0 shear runs at e = CH4_FRICTION_E bracketing the incline's bulk ν (0.81-0.83 at 10-14°).
CH4_INCLINE_NU    := 0.810 0.825
# Chapter 4, incline (gf-incline): a layer 25 diameters thick on a base 40 wide (~1000
# grains), e = 0.5; Figs 4.7-4.9 at 12°, μ = 0. TIMING: see README (gf-incline, quick size).
INCLINE_WIDTH           := 40
INCLINE_HEIGHT          := 25
INCLINE_SEED            := 1
INCLINE_E               := 0.50
INCLINE_REFERENCE_ANGLE := 12
INCLINE_ANGLES_MU0      := 10 12 14
# μ = 0.4 incline runs are left to SIZE=paper: from the dilute start the frictional collapse
# costs 818-2251 solver sweeps per step (tolerance 1e-7-1e-10; 6-11 % of the steps stop at
# the sweep limit), 10-40x the frictionless flow: ~1 CPU hour per 400 τ run (measured at
# 20° and 24°). Fig 4.10 (right) then shows the shear data only.
INCLINE_ANGLES_MU04     :=
INCLINE_CRITICAL_ANGLES := 5 7
INCLINE_TIME            := 400
INCLINE_TIME_STEP       := 5e-3
INCLINE_FROM_TIME       := 200
INCLINE_PROFILE_BLOCK   := 2000
INCLINE_FRAME_EVERY     := 10000
INCLINE_CRITICAL_WINDOW := 200
INCLINE_BASE_SKIP       := 3
INCLINE_SURFACE_SKIP    := 8
