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
SHEAR_FRAME_EVERY := 100
