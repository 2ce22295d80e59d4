# Quick reproduction: minutes on a laptop.
PACK_GRAINS := 1000
PACK_NU     := 0.600 0.700 0.760 0.800 0.820
PACK_SEEDS  := 1
