# The incline's observables against its time step (make -f Makefile.sweeps incline-step;
# pipelines/convergence.mk; another grid: INCLINE_STEP_GRID=FILE): the SIZE's μ = 0 incline runs at
# INCLINE_STEP_ANGLES at each time step of INCLINE_STEPS (in τ), which must hold the SIZE's own
# INCLINE_TIME_STEP.
INCLINE_STEPS       := 1e-2 5e-3 2.5e-3 1.25e-3
INCLINE_STEP_ANGLES := 12
