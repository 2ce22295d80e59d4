# The convergence study (make -f Makefile.sweeps convergence; pipelines/convergence.mk, results in
# docs/results/convergence.md): which observables reach a limit as the strain step γ̇dt -> 0.
# Another grid: make -f Makefile.sweeps convergence CONVERGENCE=path/to/grid.mk (the same names).
#
# State points "ν:e:μ", each run at every strain step of CONV_STEPS (at least two), N = CONV_GRAINS,
# the default tolerance. The reference point (a dilute, nearly elastic flow) gives ξ_el at each step.
CONV_POINTS       := 0.500:0.50:0.00 0.700:0.00:0.00 0.760:0.50:0.00 0.800:0.50:0.00 0.800:0.00:0.00 \
                     0.820:0.92:0.00 0.760:0.00:0.40
CONV_REFERENCE    := 0.300:0.92:0.00
CONV_STEPS        := 2e-3 1e-3 5e-4 2.5e-4 1.25e-4
# The step every figure of the reproduction uses (SHEAR_STRAIN_STEP of the quick and paper sizes).
CONV_DEFAULT_STEP := 1e-3
CONV_GRAINS       := 1000
# Finer steps at the points where the quantities of the thesis' verdicts have not settled.
CONV_FINE_POINTS  := 0.800:0.50:0.00 0.800:0.00:0.00
CONV_FINE_STEPS   := 6.25e-5
# A larger cell at two steps, to tell the size dependence from the step dependence.
CONV_LARGE_GRAINS := 4000
CONV_LARGE_POINTS := 0.800:0.50:0.00 0.800:0.00:0.00
CONV_LARGE_STEPS  := 1e-3 2.5e-4
# The solver tolerance (Υ = tolerance/dt) at one point and one step: the default and these.
CONV_TOLERANCE         := 1e-10
CONV_TOLERANCE_POINT   := 0.800:0.50:0.00
CONV_TOLERANCE_STEP    := 1e-3
CONV_OTHER_TOLERANCES  := 1e-8 1e-12
# Every run: CONV_STRAIN strain units at γ̇ = CONV_RATE from one packing per (N, ν), averages from
# CONV_FROM_STRAIN (later where the run's own transient ends), observables every
# CONV_OBSERVE_STRAIN and frames every CONV_FRAME_STRAIN of strain whatever the step, so that
# every run has the same number of rows and frames.
CONV_STRAIN        := 20
CONV_RATE          := 1
CONV_SEED          := 1
CONV_FROM_STRAIN   := 1
CONV_OBSERVE_STRAIN := 2e-3
CONV_FRAME_STRAIN  := 4e-2
# z, Φ, Ψ and the fabric also over geometric contacts (gf-network --contact-gap), these gaps in
# mean diameters.
CONV_CONTACT_GAPS  := 1e-4 1e-3 1e-2
# D²min (Fig. 6.9): maps over one frame interval from each of these strains and from two frames
# later, neighbours within CONV_D2MIN_CUTOFF mean diameters (the quick size's CH6_STZ_CUTOFF).
CONV_D2MIN_STRAINS := 2 4 6 8 10 12 14 16 18
CONV_D2MIN_CUTOFF  := 2
