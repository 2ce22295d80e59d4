# The thesis' sizes (chapter 4: N = 10^4 grains in simple shear).
PACK_GRAINS := 10000
PACK_NU     := 0.400 0.500 0.600 0.650 0.700 0.720 0.740 0.760 0.770 0.780 0.790 0.800 0.810 0.820
PACK_SEEDS  := 1
