# Chapter 6: the equilibrium-run recipe (docs/method/kinetic.md, "The recipe"), measured on the
# quick size's packings (gf-pack, N = 1000, seed 1, default polydispersity): a warm-up of
# CH6_EQ_WARMUP_STEPS at the coarse step CH6_EQ_WARMUP_DT_<ν> from the packing at T0 = 1,
# CH6_EQ_SETTLE_STEPS settling and CH6_EQ_STEPS measured steps at CH6_EQ_DT_<ν> = 2.5e-4/ω
# (ω the collision frequency at the end of the warm-up): energy drift < 0.5 % at every ν,
# χ at DT and DT/2 agreeing within errors at ν = 0.5, 0.8, 0.82; 140 s of CPU for these nine ν.
# Included by the size files whose grids use it.
CH6_EQ_WARMUP_STEPS  := 80000
CH6_EQ_SETTLE_STEPS  := 80000
CH6_EQ_STEPS         := 200000
CH6_EQ_FRAME_EVERY   := 2000
# Rows every 10 steps: the pressure of a row is one step's impulses (about 0.1 collision per
# step at ω·dt = 2.5e-4, N = 1000), heavy-tailed; every 100 steps χ_virial's error is 10 %.
CH6_EQ_OBSERVE_EVERY := 10
CH6_EQ_WARMUP_DT_0.200 := 0.008
CH6_EQ_WARMUP_DT_0.300 := 0.004
CH6_EQ_WARMUP_DT_0.400 := 0.0025
CH6_EQ_WARMUP_DT_0.500 := 0.0015
CH6_EQ_WARMUP_DT_0.600 := 8e-4
CH6_EQ_WARMUP_DT_0.700 := 3e-4
CH6_EQ_WARMUP_DT_0.760 := 1e-4
CH6_EQ_WARMUP_DT_0.800 := 1e-4
CH6_EQ_WARMUP_DT_0.820 := 2e-5
CH6_EQ_DT_0.200      := 4.4e-4
CH6_EQ_DT_0.300      := 2.3e-4
CH6_EQ_DT_0.400      := 1.4e-4
CH6_EQ_DT_0.500      := 8.1e-5
CH6_EQ_DT_0.600      := 4.2e-5
CH6_EQ_DT_0.700      := 1.6e-5
CH6_EQ_DT_0.760      := 8.2e-6
CH6_EQ_DT_0.800      := 3.2e-6
CH6_EQ_DT_0.820      := 7.3e-7
# A ν without its own steps above uses the densest measured ones (safe, only slower).
CH6_EQ_WARMUP_DT     := 2e-5
CH6_EQ_DT            := 7.3e-7
