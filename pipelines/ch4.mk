# Chapter 4, simple shear (thesis §4.2, Figs 4.1-4.6); grids in pipelines/sizes/$(SIZE).mk.
#
# Runs: $(RUNS)/shear_nu<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>.h5, gf-shear on the packing
# $(RUNS)/pack_nu<ν>_s<seed>.h5 for SHEAR_STRAIN (SHEAR_LONG_STRAIN at the ν of SHEAR_LONG_NU)
# at SHEAR_STRAIN_STEP (= γ̇dt). Any such name
# can be asked for (make -f Makefile.sweeps runs/quick/shear_nu0.780_e0.25_mu0.40_r1e+00_s1.h5).
# The strain settings belong to the SIZE and are not in the name: after changing them,
# remove the runs (clean-runs) to redo them.
# Tables (steady_state.py, one row per run): $(RUNS)/ch4_sweep.h5 (ν x e grid at CH4_RATE, μ = 0;
# and, for Fig 4.10's comparison with the incline, μ = 0.4 runs at CH4_FRICTION_NU and μ = 0 runs at
# CH4_INCLINE_NU, both at e = CH4_FRICTION_E),
# $(RUNS)/ch4_bagnold.h5 (Fig 4.2 pair). Figures: $(FIGURES)/fig4_<k>.png.
# Analyses and figures also depend on the size file: a grid or CH4_FROM_STRAIN change redoes
# them (never a simulation).

shear_run = $(RUNS)/shear_nu$(1)_e$(2)_mu$(3)_r$(4)_s$(5).h5
# Strain and frame spacing of a run at ν = $(1): SHEAR_LONG_* for the ν of SHEAR_LONG_NU (dilute
# flows sheared from rest heat up for many strain units), SHEAR_* otherwise.
shear_long        = $(filter $(1),$(SHEAR_LONG_NU))
shear_strain      = $(if $(call shear_long,$(1)),$(SHEAR_LONG_STRAIN),$(SHEAR_STRAIN))
shear_frame_every = $(if $(call shear_long,$(1)),$(SHEAR_LONG_FRAME_EVERY),$(SHEAR_FRAME_EVERY))
# μ = 0 at every e; μ = 0.4 (Fig 4.10 right, beside the incline) at CH4_FRICTION_E only.
CH4_SWEEP_RUNS    := $(foreach e,$(CH4_E),$(foreach nu,$(CH4_NU),\
                       $(call shear_run,$(nu),$(e),0.00,$(CH4_RATE),$(CH4_SEED)))) \
                     $(foreach nu,$(CH4_FRICTION_NU),$(call shear_run,$(nu),$(CH4_FRICTION_E),0.40,$(CH4_RATE),$(CH4_SEED)))
# μ = 0 at e = CH4_FRICTION_E and CH4_INCLINE_NU: shear points that bracket the incline's bulk ν.
CH4_SWEEP_RUNS    += $(filter-out $(CH4_SWEEP_RUNS),$(foreach nu,$(CH4_INCLINE_NU),\
                       $(call shear_run,$(nu),$(CH4_FRICTION_E),0.00,$(CH4_RATE),$(CH4_SEED))))
CH4_BAGNOLD_RUNS  := $(foreach r,$(CH4_BAGNOLD_RATES),$(call shear_run,$(CH4_BAGNOLD_NU),0.00,0.00,$(r),$(CH4_SEED)))
# Figs 4.1 and 4.3: the Fig 4.2 run at the first (slowest) rate.
CH4_REFERENCE_RUN := $(firstword $(CH4_BAGNOLD_RUNS))
CH4_TABLES        := $(RUNS)/ch4_sweep.h5 $(RUNS)/ch4_bagnold.h5
CH4_FIGURES       := $(foreach k,1 2 3 4 5 6,$(FIGURES)/fig4_$(k).png)
# steady_state.py takes its statistics from the shared library: its stamp is a prerequisite.
CH4_ANALYSIS      := pipelines/analysis/steady_state.py $(GRANFLOW_PY) $(STATISTICS_STAMP) pipelines/sizes/$(SIZE).mk

ch4-files: $(CH4_FIGURES) $(CH4_TABLES)

# Stem "<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>": word $(2) of the stem split at "_", prefix $(1) removed.
shear_arg = $(patsubst $(1)%,%,$(word $(2),$(subst _, ,$(3))))
.SECONDEXPANSION:
$(RUNS)/shear_nu%.h5: $(RUNS)/pack_nu$$(call shear_arg,,1,$$*)_$$(call shear_arg,,5,$$*).h5 \
                      $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear --quiet $(call resume,gf-shear) -i $< -o $@ --rate $(call shear_arg,r,4,$*) \
	  --restitution $(call shear_arg,e,2,$*) --friction $(call shear_arg,mu,3,$*) \
	  --seed $(call shear_arg,s,5,$*) --strain $(call shear_strain,$(call shear_arg,,1,$*)) \
	  --strain-step $(SHEAR_STRAIN_STEP) --frame-every $(call shear_frame_every,$(call shear_arg,,1,$*))

$(RUNS)/ch4_sweep.h5: $(CH4_SWEEP_RUNS) $(CH4_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/steady_state.py --from-strain $(CH4_FROM_STRAIN) --detect-transient -o $@ $(CH4_SWEEP_RUNS)
$(RUNS)/ch4_bagnold.h5: $(CH4_BAGNOLD_RUNS) $(CH4_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/steady_state.py --from-strain $(CH4_FROM_STRAIN) --detect-transient -o $@ $(CH4_BAGNOLD_RUNS)

$(FIGURES)/fig4_1.png: $(CH4_REFERENCE_RUN) pipelines/plot/ch4_snapshot.py $(GRANFLOW_PY) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_snapshot.py $< $@
$(FIGURES)/fig4_2.png: $(CH4_BAGNOLD_RUNS) pipelines/plot/ch4_bagnold.py $(CH4_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_bagnold.py --from-strain $(CH4_FROM_STRAIN) --detect-transient $@ $(CH4_BAGNOLD_RUNS)
$(FIGURES)/fig4_3.png: $(CH4_REFERENCE_RUN) pipelines/plot/ch4_invariants.py $(CH4_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_invariants.py --from-strain $(CH4_FROM_STRAIN) --detect-transient $< $@
$(FIGURES)/fig4_4.png: $(RUNS)/ch4_sweep.h5 pipelines/plot/ch4_rheology.py $(CH4_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_rheology.py $< $@
$(FIGURES)/fig4_5.png: $(RUNS)/ch4_sweep.h5 pipelines/plot/ch4_pressure_parts.py $(CH4_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_pressure_parts.py $< $@
$(FIGURES)/fig4_6.png: $(RUNS)/ch4_sweep.h5 pipelines/plot/ch4_static_pressure.py $(CH4_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_static_pressure.py $< $@

# The report's chapter-4 section.
$(FIGURES)/REPORT.md: $(CH4_TABLES) $(CH4_REFERENCE_RUN) $(CH4_ANALYSIS)
REPORT_ARGS += --ch4-sweep $(RUNS)/ch4_sweep.h5 --ch4-bagnold $(RUNS)/ch4_bagnold.h5 \
               --ch4-reference $(CH4_REFERENCE_RUN)
