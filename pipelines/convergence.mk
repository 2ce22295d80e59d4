# The convergence study: every observable of the reproduction against the strain step γ̇dt
# (results: docs/results/convergence.md). The grid is the file $(CONVERGENCE) (default
# pipelines/sizes/convergence.mk), independent of SIZE; its runs go to $(CONV_RUNS).
#
# Runs: $(CONV_RUNS)/conv_n<N>_nu<ν>_e<e>_mu<μ>_dt<γ̇dt>_tol<tolerance>_s<seed>.h5, gf-shear from
# the packing $(CONV_RUNS)/pack_n<N>_nu<ν>_s<seed>.h5, CONV_STRAIN strain units, an observable row
# every CONV_OBSERVE_STRAIN and a frame every CONV_FRAME_STRAIN of strain, contact activation
# CONV_ACTIVATION (gf-shear --activation; a grid of another activation sets its own CONV_RUNS, as
# pipelines/sizes/convergence_overlap.mk does). Any such name can be
# asked for. Per run, its own tables (so that adding a step or a point analyses only the new runs):
# steady_<stem> (steady_state.py: p, s/p, T, p^s, p^k), correlate_<stem> (gf-correlate, ξ_el from
# the reference point's run at the same N and step), network_<stem> (gf-network with that table),
# kinetic_<stem> (gf-kinetic: C_v, collisions) and network_gap<H>_<stem> (gf-network over
# geometric contacts within H mean diameters, each H of CONV_CONTACT_GAPS) and d2min_<stem>
# (gf-stz d2min maps from each strain of CONV_D2MIN_STRAINS, d2min_statistics.py). The summary,
# convergence.h5 and convergence.md (pipelines/analysis/convergence.py): per state point and
# observable, the values against the
# step and the class (converged, converging with its limit, regularisation-dependent with its
# exponent, or unsettled), convergence_classes.csv (the classes alone, which the report,
# pipelines/report/, reads from its committed copy docs/results/convergence_classes.csv),
# convergence_series.csv (every value, committed as docs/results/convergence_series.csv) and
# $(FIGURES)/fig4_2_step.png, Fig. 4.2's companion at fixed γ̇.
CONVERGENCE ?= pipelines/sizes/convergence.mk
include $(CONVERGENCE)
CONV_RUNS ?= runs/convergence
CONV_ACTIVATION ?= predicted-gap

ifneq ($(filter convergence convergence-files,$(MAKECMDGOALS)),)
ifeq ($(word 2,$(CONV_STEPS)),)
$(error $(CONVERGENCE): CONV_STEPS needs at least two strain steps (got '$(strip $(CONV_STEPS))'))
endif
ifeq ($(filter $(CONV_DEFAULT_STEP),$(CONV_STEPS)),)
$(error $(CONVERGENCE): CONV_DEFAULT_STEP ($(CONV_DEFAULT_STEP)) is not one of CONV_STEPS)
endif
ifeq ($(strip $(CONV_POINTS)),)
$(error $(CONVERGENCE): CONV_POINTS is empty)
endif
ifneq ($(words $(CONV_REFERENCE)),1)
$(error $(CONVERGENCE): CONV_REFERENCE must be one point ν:e:μ (got '$(strip $(CONV_REFERENCE))'))
endif
endif

# Word $(2) of a point "ν:e:μ".
conv_part = $(word $(2),$(subst :, ,$(1)))
# Run of point $(2) at N = $(1), step $(3), tolerance $(4).
conv_run = $(CONV_RUNS)/conv_n$(1)_nu$(call conv_part,$(2),1)_e$(call conv_part,$(2),2)_mu$(call conv_part,$(2),3)_dt$(3)_tol$(4)_s$(CONV_SEED).h5
# Runs of the points $(2) at N = $(1), each step of $(3), each tolerance of $(4).
conv_grid = $(foreach p,$(2),$(foreach d,$(3),$(foreach t,$(4),$(call conv_run,$(1),$(p),$(d),$(t)))))
CONV_SIM := $(call conv_grid,$(CONV_GRAINS),$(CONV_POINTS) $(CONV_REFERENCE),$(CONV_STEPS),$(CONV_TOLERANCE)) \
            $(call conv_grid,$(CONV_GRAINS),$(if $(CONV_FINE_STEPS),$(CONV_FINE_POINTS) $(CONV_REFERENCE)),$(CONV_FINE_STEPS),$(CONV_TOLERANCE)) \
            $(if $(CONV_LARGE_GRAINS),$(call conv_grid,$(CONV_LARGE_GRAINS),$(CONV_LARGE_POINTS) $(CONV_REFERENCE),$(CONV_LARGE_STEPS),$(CONV_TOLERANCE))) \
            $(call conv_grid,$(CONV_GRAINS),$(if $(CONV_OTHER_TOLERANCES),$(CONV_TOLERANCE_POINT)),$(CONV_TOLERANCE_STEP),$(CONV_OTHER_TOLERANCES))
CONV_SIM := $(sort $(CONV_SIM))
CONV_STEMS := $(patsubst $(CONV_RUNS)/conv_n%.h5,%,$(CONV_SIM))
CONV_TABLES := $(foreach k,steady correlate network kinetic d2min $(CONV_CONTACT_GAPS:%=network_gap%),\
                 $(CONV_STEMS:%=$(CONV_RUNS)/$(k)_n%.h5))
CONV_SUMMARY := $(CONV_RUNS)/convergence.h5 $(CONV_RUNS)/convergence.md $(CONV_RUNS)/convergence_classes.csv \
                $(CONV_RUNS)/convergence_series.csv
CONV_ANALYSIS := $(GRANFLOW_PY) $(CONVERGENCE)

CONV_FIGURE ?= $(FIGURES)/fig4_2_step.png
convergence-files: $(CONV_SUMMARY) $(CONV_FIGURE)

# Stem "<N>_nu<ν>_e<e>_mu<μ>_dt<γ̇dt>_tol<tol>_s<seed>": word $(2) split at "_", prefix $(1) removed.
conv_arg = $(patsubst $(1)%,%,$(word $(2),$(subst _, ,$(3))))
# Steps between rows (frames) for a strain interval $(1) at step $(2): the nearest integer, at least 1.
conv_every = $$(awk 'BEGIN { k = int($(1) / $(2) + 0.5); print (k < 1 ? 1 : k) }')
# The reference run at the N and step of stem $(1) (default tolerance).
conv_reference = $(CONV_RUNS)/conv_n$(call conv_arg,,1,$(1))_nu$(call conv_part,$(CONV_REFERENCE),1)_e$(call conv_part,$(CONV_REFERENCE),2)_mu$(call conv_part,$(CONV_REFERENCE),3)_$(call conv_arg,,5,$(1))_tol$(CONV_TOLERANCE)_$(call conv_arg,,7,$(1)).h5

$(CONV_RUNS)/pack_n%.h5: $(STAMPS)/gf-pack.stamp | $(CONV_RUNS)/
	$(LAUNCH) $(BIN)/gf-pack --quiet --grains $(call conv_arg,,1,$*) --packing-fraction $(call conv_arg,nu,2,$*) \
	  --seed $(call conv_arg,s,3,$*) -o $@
$(CONV_RUNS)/conv_n%.h5: $(CONV_RUNS)/pack_n$$(call conv_arg,,1,$$*)_$$(call conv_arg,,2,$$*)_$$(call conv_arg,,7,$$*).h5 \
                         $(STAMPS)/gf-shear.stamp | $(CONV_RUNS)/
	$(LAUNCH) $(BIN)/gf-shear --quiet $(call resume,gf-shear) -i $< -o $@ --rate $(CONV_RATE) \
	  --restitution $(call conv_arg,e,3,$*) --friction $(call conv_arg,mu,4,$*) --seed $(call conv_arg,s,7,$*) \
	  --strain $(CONV_STRAIN) --strain-step $(call conv_arg,dt,5,$*) --tolerance $(call conv_arg,tol,6,$*) \
	  --activation $(CONV_ACTIVATION) \
	  --observe-every $(call conv_every,$(CONV_OBSERVE_STRAIN),$(call conv_arg,dt,5,$*)) \
	  --frame-every $(call conv_every,$(CONV_FRAME_STRAIN),$(call conv_arg,dt,5,$*))

$(CONV_RUNS)/steady_n%.h5: $(CONV_RUNS)/conv_n%.h5 pipelines/analysis/steady_state.py $(STATISTICS_STAMP) $(CONV_ANALYSIS)
	$(PYTHON) pipelines/analysis/steady_state.py --from-strain $(CONV_FROM_STRAIN) --detect-transient -o $@ $<
$(CONV_RUNS)/correlate_n%.h5: $(CONV_RUNS)/conv_n%.h5 $$(call conv_reference,$$*) $(STAMPS)/gf-correlate.stamp $(CONV_ANALYSIS)
	$(LAUNCH) $(BIN)/gf-correlate --quiet -o $@ --from-strain $(CONV_FROM_STRAIN) --detect-transient \
	  --reference $(call conv_reference,$*) $<
$(CONV_RUNS)/network_n%.h5: $(CONV_RUNS)/conv_n%.h5 $(CONV_RUNS)/correlate_n%.h5 $(STAMPS)/gf-network.stamp $(CONV_ANALYSIS)
	$(LAUNCH) $(BIN)/gf-network --quiet -o $@ --from-strain $(CONV_FROM_STRAIN) --detect-transient \
	  --correlation $(CONV_RUNS)/correlate_n$*.h5 $<
# Over geometric contacts within H mean diameters (gf-network --contact-gap H): stem
# "<H>_n<run stem>"; conv_gap_run gives the run stem.
conv_gap_run = $(patsubst $(call conv_arg,,1,$(1))_n%,%,$(1))
$(CONV_RUNS)/network_gap%.h5: $(CONV_RUNS)/conv_n$$(call conv_gap_run,$$*).h5 \
                              $(CONV_RUNS)/correlate_n$$(call conv_gap_run,$$*).h5 $(STAMPS)/gf-network.stamp $(CONV_ANALYSIS)
	$(LAUNCH) $(BIN)/gf-network --quiet -o $@ --from-strain $(CONV_FROM_STRAIN) --detect-transient \
	  --contact-gap $(call conv_arg,,1,$*) --correlation $(CONV_RUNS)/correlate_n$(call conv_gap_run,$*).h5 $<
$(CONV_RUNS)/kinetic_n%.h5: $(CONV_RUNS)/conv_n%.h5 $(STAMPS)/gf-kinetic.stamp $(CONV_ANALYSIS)
	$(LAUNCH) $(BIN)/gf-kinetic --quiet -o $@ --from-strain $(CONV_FROM_STRAIN) --detect-transient $<
# D²min (Fig. 6.9's numbers): from each strain s of CONV_D2MIN_STRAINS, gf-stz d2min over one frame
# interval (CONV_FRAME_STRAIN) from s and over the one two frames later, neighbours within
# CONV_D2MIN_CUTOFF mean diameters (the maps in $@.maps, removed once read); d2min_statistics.py: the
# black fraction, median, clusters and J of the two maps, with errors over the starts.
$(CONV_RUNS)/d2min_n%.h5: $(CONV_RUNS)/conv_n%.h5 $(STAMPS)/gf-stz.stamp pipelines/analysis/d2min_statistics.py \
                          pipelines/analysis/d2min_maps.py $(CONV_ANALYSIS)
	rm -rf $@.maps && mkdir $@.maps
	set -e; maps=; for s in $(CONV_D2MIN_STRAINS); do \
	  k=$$(awk "BEGIN { print int($$s / $(CONV_FRAME_STRAIN) + 0.5) }"); \
	  for a in $$k $$((k + 2)); do \
	    $(LAUNCH) $(BIN)/gf-stz d2min --quiet --cutoff $(CONV_D2MIN_CUTOFF) -i $< --frames $$a,$$((a + 1)) \
	      -o $@.maps/$$a.h5; \
	    maps="$$maps $@.maps/$$a.h5"; \
	  done; \
	done; \
	$(PYTHON) pipelines/analysis/d2min_statistics.py -o $@ $$maps
	rm -rf $@.maps

$(CONV_SUMMARY) &: $(CONV_TABLES) pipelines/analysis/convergence.py $(STATISTICS_STAMP) $(CONV_ANALYSIS) | $(CONV_RUNS)/
	$(PYTHON) pipelines/analysis/convergence.py --default-step $(CONV_DEFAULT_STEP) \
	  --reference $(CONV_REFERENCE) -o $(CONV_RUNS)/convergence.h5 --markdown $(CONV_RUNS)/convergence.md \
	  --classes-csv $(CONV_RUNS)/convergence_classes.csv --series-csv $(CONV_RUNS)/convergence_series.csv \
	  $(CONV_TABLES)

# Fig. 4.2's companion: p, s/p and T against the step at fixed γ̇.
$(CONV_FIGURE): $(CONV_RUNS)/convergence.h5 pipelines/plot/convergence_step.py $(GRANFLOW_PY) | $(FIGURES)/
	$(PYTHON) pipelines/plot/convergence_step.py $< $@

# ν_bc(e) and the dense/dilute class of every run against the step (Figs 5.9-5.10; grid file
# $(PHASE_GRID)): the SIZE's chapter-5 sweep at μ = 0 over PHASE_NU (and its reference run), made again in
# $(CONV_RUNS)/ch5_dt<h> at each step h of PHASE_STEPS by a sub-make of the SIZE's own rules with
# SHEAR_STRAIN_STEP = h and frames at the SIZE's strain spacing; then phase_step.py:
# $(CONV_RUNS)/phase_step.{h5,md} and $(FIGURES)/fig5_10_step.png. The sub-make is always asked
# (it alone knows the runs); it remakes only what is out of date.
PHASE_GRID ?= pipelines/sizes/phase_step.mk
include $(PHASE_GRID)
PHASE_TABLES  := $(PHASE_STEPS:%=$(CONV_RUNS)/ch5_dt%/ch5_correlate.h5)
PHASE_SUMMARY := $(CONV_RUNS)/phase_step.h5 $(CONV_RUNS)/phase_step.md $(FIGURES)/fig5_10_step.png
phase-step-files: $(PHASE_SUMMARY)

ifneq ($(filter phase-step phase-step-files,$(MAKECMDGOALS)),)
ifeq ($(word 2,$(PHASE_STEPS)),)
$(error $(PHASE_GRID): PHASE_STEPS needs at least two strain steps (got '$(strip $(PHASE_STEPS))'))
endif
ifeq ($(filter $(SHEAR_STRAIN_STEP),$(PHASE_STEPS)),)
$(error $(PHASE_GRID): PHASE_STEPS must hold the SIZE's step SHEAR_STRAIN_STEP ($(SHEAR_STRAIN_STEP)))
endif
endif

# Always out of date: a step study's per-step table is asked of its sub-make every time.
.PHONY: step-study-force
step-study-force:
$(CONV_RUNS)/ch5_dt%/ch5_correlate.h5: step-study-force
	+$(MAKE) --no-print-directory -f $(SELF) RUNS=$(@D) SHEAR_STRAIN_STEP=$* \
	  SHEAR_FRAME_EVERY=$(call conv_every,$(SHEAR_FRAME_EVERY)*$(SHEAR_STRAIN_STEP),$*) \
	  SHEAR_LONG_FRAME_EVERY=$(call conv_every,$(SHEAR_LONG_FRAME_EVERY)*$(SHEAR_STRAIN_STEP),$*) \
	  CH5_MU= CH5_NU="$(PHASE_NU)" $@

$(PHASE_SUMMARY) &: $(PHASE_TABLES) pipelines/analysis/phase_step.py pipelines/analysis/convergence.py \
                    $(GRANFLOW_PY) $(PHASE_GRID) | $(CONV_RUNS)/ $(FIGURES)/
	$(PYTHON) pipelines/analysis/phase_step.py --default-step $(SHEAR_STRAIN_STEP) -o $(CONV_RUNS)/phase_step.h5 \
	  --markdown $(CONV_RUNS)/phase_step.md --figure $(FIGURES)/fig5_10_step.png $(PHASE_TABLES)

# The incline's observables against its time step (Figs 4.8-4.10; grid file $(INCLINE_STEP_GRID)):
# the SIZE's μ = 0 incline runs at INCLINE_STEP_ANGLES, made again in $(CONV_RUNS)/incline_dt<h> at
# each time step h (in τ) of INCLINE_STEPS by a sub-make of the SIZE's own rules, frames and
# profile blocks at the SIZE's spacing in time, no μ = 0.4 branches; then incline_step.py:
# $(CONV_RUNS)/incline_step.{h5,md}. The sub-make is always asked; it remakes only what is out of date.
INCLINE_STEP_GRID ?= pipelines/sizes/incline_step.mk
include $(INCLINE_STEP_GRID)
INCLINE_STEP_TABLES  := $(INCLINE_STEPS:%=$(CONV_RUNS)/incline_dt%/ch4_incline.h5)
INCLINE_STEP_SUMMARY := $(CONV_RUNS)/incline_step.h5 $(CONV_RUNS)/incline_step.md
incline-step-files: $(INCLINE_STEP_SUMMARY)

ifneq ($(filter incline-step incline-step-files,$(MAKECMDGOALS)),)
ifeq ($(word 2,$(INCLINE_STEPS)),)
$(error $(INCLINE_STEP_GRID): INCLINE_STEPS needs at least two time steps (got '$(strip $(INCLINE_STEPS))'))
endif
ifeq ($(filter $(INCLINE_TIME_STEP),$(INCLINE_STEPS)),)
$(error $(INCLINE_STEP_GRID): INCLINE_STEPS must hold the SIZE's step INCLINE_TIME_STEP ($(INCLINE_TIME_STEP)))
endif
endif

$(CONV_RUNS)/incline_dt%/ch4_incline.h5: step-study-force
	+$(MAKE) --no-print-directory -f $(SELF) RUNS=$(@D) INCLINE_TIME_STEP=$* \
	  INCLINE_FRAME_EVERY=$(call conv_every,$(INCLINE_FRAME_EVERY)*$(INCLINE_TIME_STEP),$*) \
	  INCLINE_PROFILE_BLOCK=$(call conv_every,$(INCLINE_PROFILE_BLOCK)*$(INCLINE_TIME_STEP),$*) \
	  INCLINE_ANGLES_MU0="$(INCLINE_STEP_ANGLES)" INCLINE_ANGLES_MU04= $@

$(INCLINE_STEP_SUMMARY) &: $(INCLINE_STEP_TABLES) pipelines/analysis/incline_step.py pipelines/analysis/convergence.py \
                           pipelines/analysis/critical_angle.py $(GRANFLOW_PY) $(INCLINE_STEP_GRID) | $(CONV_RUNS)/
	$(PYTHON) pipelines/analysis/incline_step.py --default-step $(INCLINE_TIME_STEP) --window $(INCLINE_CRITICAL_WINDOW) \
	  -o $(CONV_RUNS)/incline_step.h5 --markdown $(CONV_RUNS)/incline_step.md $(INCLINE_STEP_TABLES)
