# Chapter 4, incline flow (thesis §4.3–4.4, Figs 4.7–4.10, critical angle θ_c); grids and run
# lengths in pipelines/sizes/$(SIZE).mk. Included after ch4.mk (uses shear_arg, CH4_ANALYSIS and
# the sweep table $(RUNS)/ch4_sweep.h5, whose μ = 0.4 rows Fig 4.10 needs).
#
# Start: $(RUNS)/incline_pack_w<W>_h<H>_s<seed>.h5, gf-pack --incline (a dilute layer above a
# base of fixed grains, W mean diameters wide, enough grains for H diameters at ν ≈ 0.8).
# Runs: $(RUNS)/incline_th<θ>_e<e>_mu<μ>_s<seed>.h5, gf-incline at angle θ (degrees) from the
# start of size INCLINE_WIDTH x INCLINE_HEIGHT and that seed, for INCLINE_TIME τ at
# INCLINE_TIME_STEP τ (τ = √(⟨R⟩/g)); profiles averaged from INCLINE_FROM_TIME τ (empty: the
# steady part detected by gf-incline, MSER). Any such name can be asked for. The time settings
# are not in the names: after changing them remove the runs (clean-runs); a change of width or
# height makes a new start and so re-runs.
# Branched runs: $(RUNS)/incline_branch_th<θ>_e<e>_mu<μ>_s<seed>_from<θp>.h5, gf-incline at θ and μ from
# the last frame of the μ = 0 run $(RUNS)/incline_th<θp>_e<e>_mu0.00_s<seed>.h5 (a dense layer
# already flowing: the frictional collapse from the dilute start is the dear part, see
# docs/results/chapter4.md, Incline), for INCLINE_BRANCH_TIME τ at INCLINE_BRANCH_TIME_STEP with solver tolerance
# INCLINE_BRANCH_TOLERANCE (empty: gf-incline's default), averaged from INCLINE_BRANCH_FROM_TIME τ
# (empty: MSER). The parent is a prerequisite, so a change of the parent re-runs the branch. (A
# rule of its own: make does not chain one pattern rule twice, so a parent outside the grids
# could not be made through the same rule.)
# The μ = 0.4 runs of Fig 4.10 branch from INCLINE_MU04_PARENT (an angle; empty: they start
# from the pack like the μ = 0 runs, with the INCLINE_* time settings).
# Tables: $(RUNS)/ch4_incline.h5 (incline_bulk.py: bulk invariants, ν, momentum balance and the
# V_x exponent per flowing run) and $(RUNS)/ch4_critical_angle.h5 (critical_angle.py: flowing or
# not per angle, θ_c with its bracket). Figures: $(FIGURES)/fig4_7.png … fig4_10.png.

# Fig 4.10 compares the incline with the shear sweep's rows at the incline's restitution.
ifneq ($(strip $(CH4_FRICTION_E)),$(strip $(INCLINE_E)))
$(warning CH4_FRICTION_E ($(CH4_FRICTION_E)) differs from INCLINE_E ($(INCLINE_E)): Fig 4.10 (μ = 0.4) will lack shear data)
endif

incline_pack = $(RUNS)/incline_pack_w$(INCLINE_WIDTH)_h$(INCLINE_HEIGHT)_s$(1).h5
incline_run  = $(RUNS)/incline_th$(1)_e$(2)_mu$(3)_s$(4).h5
# Branch at θ = $(1), e = $(2), μ = $(3), seed $(4) from the μ = 0 run at θp = $(5).
incline_branch = $(RUNS)/incline_branch_th$(1)_e$(2)_mu$(3)_s$(4)_from$(5).h5
# The parent of a branch stem "<θ>_e<e>_mu<μ>_s<seed>_from<θp>": the μ = 0 run at θp.
incline_parent = $(call incline_run,$(call shear_arg,from,5,$(1)),$(call shear_arg,e,2,$(1)),0.00,$(call shear_arg,s,4,$(1)))
# μ = 0.4 runs of Fig 4.10: branched from INCLINE_MU04_PARENT, or from the pack.
incline_mu04_run = $(if $(strip $(INCLINE_MU04_PARENT)),\
                     $(call incline_branch,$(1),$(INCLINE_E),0.40,$(INCLINE_SEED),$(strip $(INCLINE_MU04_PARENT))),\
                     $(call incline_run,$(1),$(INCLINE_E),0.40,$(INCLINE_SEED)))
# Flowing runs for the bulk rheology (Fig 4.10): every angle of each friction.
INCLINE_FLOW_RUNS := $(foreach th,$(INCLINE_ANGLES_MU0),$(call incline_run,$(th),$(INCLINE_E),0.00,$(INCLINE_SEED))) \
                     $(foreach th,$(INCLINE_ANGLES_MU04),$(strip $(call incline_mu04_run,$(th))))
# θ_c sweep (μ = 0): the extra low angles and the flowing ones, each run once.
INCLINE_CRITICAL_RUNS := $(sort $(foreach th,$(INCLINE_CRITICAL_ANGLES) $(INCLINE_ANGLES_MU0),\
                           $(call incline_run,$(th),$(INCLINE_E),0.00,$(INCLINE_SEED))))
# Figs 4.7–4.9: θ = INCLINE_REFERENCE_ANGLE (12°), μ = 0.
INCLINE_REFERENCE_RUN := $(call incline_run,$(INCLINE_REFERENCE_ANGLE),$(INCLINE_E),0.00,$(INCLINE_SEED))
INCLINE_TABLES    := $(RUNS)/ch4_incline.h5 $(RUNS)/ch4_critical_angle.h5
INCLINE_FIGURES   := $(foreach k,7 8 9 10,$(FIGURES)/fig4_$(k).png)
INCLINE_ANALYSIS  := pipelines/analysis/incline_bulk.py $(GRANFLOW_PY) pipelines/sizes/$(SIZE).mk
INCLINE_BULK_ARGS := --base-skip $(INCLINE_BASE_SKIP) --surface-skip $(INCLINE_SURFACE_SKIP)

ch4-files: $(INCLINE_FIGURES) $(INCLINE_TABLES)
ch4-incline: build
	+$(MAKE) -f $(SELF) ch4-incline-files
ch4-incline-files: $(INCLINE_FIGURES) $(INCLINE_TABLES)

# Stem "<W>_h<H>_s<seed>".
$(RUNS)/incline_pack_w%.h5: $(STAMPS)/gf-pack.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-pack --quiet --incline --width $(call shear_arg,,1,$*) \
	  --height $(call shear_arg,h,2,$*) --seed $(call shear_arg,s,3,$*) -o $@

# Stem "<θ>_e<e>_mu<μ>_s<seed>".
$(RUNS)/incline_th%.h5: $$(call incline_pack,$$(call shear_arg,s,4,$$*)) $(STAMPS)/gf-incline.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-incline --quiet $(call resume,gf-incline) -i $< -o $@ --angle $(call shear_arg,,1,$*) \
	  --restitution $(call shear_arg,e,2,$*) --friction $(call shear_arg,mu,3,$*) \
	  --time $(INCLINE_TIME) --time-step $(INCLINE_TIME_STEP) $(if $(INCLINE_FROM_TIME),--from-time $(INCLINE_FROM_TIME)) \
	  --frame-every $(INCLINE_FRAME_EVERY) --profile-block $(INCLINE_PROFILE_BLOCK)

# Stem "<θ>_e<e>_mu<μ>_s<seed>_from<θp>": from the last frame of the parent.
$(RUNS)/incline_branch_th%.h5: $$(call incline_parent,$$*) $(STAMPS)/gf-incline.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-incline --quiet $(call resume,gf-incline) -i $< -o $@ --angle $(call shear_arg,,1,$*) \
	  --restitution $(call shear_arg,e,2,$*) --friction $(call shear_arg,mu,3,$*) --frame -1 \
	  --time $(INCLINE_BRANCH_TIME) --time-step $(INCLINE_BRANCH_TIME_STEP) \
	  $(if $(INCLINE_BRANCH_FROM_TIME),--from-time $(INCLINE_BRANCH_FROM_TIME)) \
	  $(if $(INCLINE_BRANCH_TOLERANCE),--tolerance $(INCLINE_BRANCH_TOLERANCE)) \
	  --frame-every $(INCLINE_FRAME_EVERY) --profile-block $(INCLINE_PROFILE_BLOCK)

$(RUNS)/ch4_incline.h5: $(INCLINE_FLOW_RUNS) $(INCLINE_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/incline_bulk.py $(INCLINE_BULK_ARGS) -o $@ $(INCLINE_FLOW_RUNS)
$(RUNS)/ch4_critical_angle.h5: $(INCLINE_CRITICAL_RUNS) pipelines/analysis/critical_angle.py $(INCLINE_ANALYSIS) \
                               pipelines/analysis/steady_state.py python/granflow/statistics.py $(STATISTICS_STAMP) \
                               | $(RUNS)/
	$(PYTHON) pipelines/analysis/critical_angle.py --window $(INCLINE_CRITICAL_WINDOW) -o $@ $(INCLINE_CRITICAL_RUNS)

$(FIGURES)/fig4_7.png: $(INCLINE_REFERENCE_RUN) pipelines/plot/ch4_incline_snapshot.py $(GRANFLOW_PY) \
                       | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_incline_snapshot.py $< $@
$(FIGURES)/fig4_8.png: $(INCLINE_REFERENCE_RUN) pipelines/plot/ch4_incline_profiles.py $(INCLINE_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_incline_profiles.py $(INCLINE_BULK_ARGS) $< $@
$(FIGURES)/fig4_9.png: $(INCLINE_REFERENCE_RUN) pipelines/plot/ch4_incline_invariants.py $(INCLINE_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_incline_invariants.py $(INCLINE_BULK_ARGS) $< $@
$(FIGURES)/fig4_10.png: $(RUNS)/ch4_incline.h5 $(RUNS)/ch4_sweep.h5 pipelines/plot/ch4_consistent_rheology.py \
                        $(INCLINE_ANALYSIS) $(CH4_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch4_consistent_rheology.py --restitution $(INCLINE_E) $(RUNS)/ch4_incline.h5 \
	  $(RUNS)/ch4_sweep.h5 $@

# The report's incline section.
$(FIGURES)/REPORT.md: $(INCLINE_TABLES) $(INCLINE_REFERENCE_RUN) $(INCLINE_ANALYSIS) pipelines/analysis/critical_angle.py
REPORT_ARGS += --ch4-incline $(RUNS)/ch4_incline.h5 --ch4-critical $(RUNS)/ch4_critical_angle.h5
