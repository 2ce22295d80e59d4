# The thesis' sizes (chapter 4: N = 10^4 grains in simple shear).
PACK_GRAINS := 10000
PACK_NU     := 0.400 0.500 0.600 0.650 0.700 0.720 0.740 0.760 0.770 0.780 0.790 0.800 0.810 0.820
PACK_SEEDS  := 1
# Chapter 4, simple shear: the thesis' ν range (Fig 4.5 shows the static/kinetic crossover
# at ν ≈ 0.4, so the grid starts below it; dense steps of 0.01 up to 0.83 < ν_max = 0.84),
# restitutions 0, 0.25, 0.5, 0.75, 0.92; Fig 4.2 at ν = 0.8 with γ̇ = 1e-2 and 1e2.
CH4_NU            := 0.100 0.200 0.300 $(PACK_NU) 0.830
CH4_E             := 0.00 0.25 0.50 0.75 0.92
CH4_RATE          := 1e-02
CH4_BAGNOLD_NU    := 0.800
CH4_BAGNOLD_RATES := 1e-02 1e+02
CH4_SEED          := 1
CH4_FROM_STRAIN   := 0.5
SHEAR_STRAIN      := 20
SHEAR_STRAIN_STEP := 1e-3
SHEAR_FRAME_EVERY := 1000
