# Tiny sweep for the pipeline tests: seconds.
PACK_GRAINS := 64
PACK_NU     := 0.500 0.700
PACK_SEEDS  := 1 2
