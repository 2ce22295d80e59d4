# ν_bc(e) of Figs 5.9-5.10 against the strain step (make -f Makefile.sweeps phase-step;
# pipelines/convergence.mk; another grid: PHASE_GRID=FILE): the SIZE's chapter-5 sweep at μ = 0 over
# PHASE_NU (the ν where ξ_|C|/ξ_el crosses 1.25, and the reference run) at each step of PHASE_STEPS,
# which must hold the SIZE's own SHEAR_STRAIN_STEP.
PHASE_STEPS := 1e-3 2.5e-4 1.25e-4 6.25e-5
PHASE_NU    := 0.700 0.740 0.760 0.770 0.780 0.790 0.800 0.810 0.820
