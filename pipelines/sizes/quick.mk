# Quick reproduction: minutes on a laptop.
PACK_GRAINS := 1000
PACK_NU     := 0.300 0.400 0.500 0.600 0.700 0.760 0.800 0.820
PACK_SEEDS  := 1
# Chapter 4, simple shear (gf-shear): the ν grid of Figs 4.4-4.6 at CH4_RATE for every
# restitution of Fig 4.6 (e = 0 serves Figs 4.4, 4.5), and the Bagnold pair of Fig 4.2
# (ν = CH4_BAGNOLD_NU, e = 0, two rates, same packing); ν from 0.3 so that Fig 4.5 shows
# the static/kinetic crossover. Budget: the 41 runs take 2.5 min CPU (7 min wall with -j1
# on this 2-core machine under a load of 4); SHEAR_STRAIN is the knob (make SHEAR_STRAIN=3 ...).
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
