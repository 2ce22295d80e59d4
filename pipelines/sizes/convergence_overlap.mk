# The convergence study under the thesis' contact activation (App. A.1; gf-shear --activation
# overlap): make -f Makefile.sweeps convergence CONVERGENCE=pipelines/sizes/convergence_overlap.mk
# (results in docs/results/convergence.md, "The thesis' activation"). The default grid's settings
# at the two ν = 0.80 points and the reference, every step of CONV_STEPS, N = 1000, the default
# tolerance; its own runs directory.
include pipelines/sizes/convergence.mk
CONV_ACTIVATION       := overlap
CONV_RUNS             := runs/convergence-overlap
CONV_POINTS           := 0.800:0.50:0.00 0.800:0.00:0.00
CONV_FINE_POINTS      :=
CONV_FINE_STEPS       :=
CONV_LARGE_GRAINS     :=
CONV_OTHER_TOLERANCES :=
CONV_FIGURE            = $(FIGURES)/fig4_2_step_overlap.png
