# Chapter 6, kinetic theory (thesis §6.1, Figs 6.1-6.3); grids in pipelines/sizes/$(SIZE).mk.
#
# Equilibrium runs (χ, the pair correlation at contact, from the collision frequency):
# $(RUNS)/eq_nu<ν>_s<seed>.h5 for every ν of CH6_EQ_NU (a ν of PACK_NU: made from the packing
# of that ν), gf-shear --rate 0 --restitution 1 after two discarded warm-ups (below: the
# packing's exactly touching pairs make the first step inject energy).
# Like the shear run lengths, these settings are not in the names: after changing them, remove
# the runs (clean-runs).
# Table: $(RUNS)/ch6_kinetic.h5, gf-kinetic over the μ = 0 runs of the chapter-4 sweep at
# CH4_RATE (the same shear runs chapters 4 and 5 use: no new shear runs), with the equilibrium
# runs; gf-kinetic's window rule is gf-correlate's (--from-strain CH6_FROM_STRAIN
# --detect-transient). Figures $(FIGURES)/fig6_{1,2,3}.png: pipelines/plot/ch6_kinetic.py over
# the table and gf-correlate's chapter-5 table (ξ/ξ_el colours the points), one restitution
# pair each. A change of gf-kinetic's code redoes the table, the figures and the report only.

CH6_EQ_NU          ?= $(CH4_NU)
CH6_EQ_SEED        ?= $(CH4_SEED)
eq_run              = $(RUNS)/eq_nu$(1)_s$(2).h5
CH6_EQ_RUNS        := $(foreach nu,$(CH6_EQ_NU),$(call eq_run,$(nu),$(CH6_EQ_SEED)))
# The rows of the table: every μ = 0 run of the chapter-4 ν × e grid.
CH6_RUNS           := $(foreach e,$(CH4_E),$(foreach nu,$(CH4_NU),\
                        $(call shear_run,$(nu),$(e),0.00,$(CH4_RATE),$(CH4_SEED))))
CH6_TABLE          := $(RUNS)/ch6_kinetic.h5
CH6_ANALYSIS       := $(GRANFLOW_PY) pipelines/sizes/$(SIZE).mk
# The restitution pair of each figure (thesis Figs 6.1, 6.2, 6.3).
CH6_PAIR_1         := 0.92 0.75
CH6_PAIR_2         := 0.50 0.25
CH6_PAIR_3         := 0.10 0.00
# A figure whose pair has no restitution in CH4_E (a small size's grid) is left out.
CH6_FIGURES        := $(foreach k,1 2 3,$(if $(filter $(CH6_PAIR_$(k)),$(CH4_E)),$(FIGURES)/fig6_$(k).png))
# gf-kinetic's settings beyond its defaults (e.g. --extrapolate).
CH6_KINETIC_ARGS   ?=

ch6-files: $(CH6_FIGURES) $(CH6_TABLE)

# Stem "<ν>_s<seed>", as for the packings. Up to three runs per ν (docs/method/kinetic.md,
# "The recipe"): a warm-up from the packing at --temperature 1 with the coarse step
# CH6_EQ_WARMUP_DT_<ν> (eqwarm_*: it takes the first step's energy injection, relaxes the
# packing's structure and equipartitions), a settling run at the production step
# CH6_EQ_DT_<ν> (eqsettle_*), both discarded, then the measured run (eq_*) at that step; each
# starts from the last frame of the one before (--rate 0 keeps a moving frame's velocities).
# CH6_EQ_WARMUP_STEPS or CH6_EQ_SETTLE_STEPS = 0 leaves that stage out; a ν without its own
# step uses CH6_EQ_WARMUP_DT / CH6_EQ_DT.
ch6_nu        = $(word 1,$(subst _s, ,$(1)))
ch6_seed      = $(word 2,$(subst _s, ,$(1)))
ch6_dt_warm   = $(or $(CH6_EQ_WARMUP_DT_$(call ch6_nu,$(1))),$(CH6_EQ_WARMUP_DT))
ch6_dt        = $(or $(CH6_EQ_DT_$(call ch6_nu,$(1))),$(CH6_EQ_DT))
ch6_warm      = $(filter-out 0,$(CH6_EQ_WARMUP_STEPS))
ch6_settle    = $(filter-out 0,$(CH6_EQ_SETTLE_STEPS))
ch6_settle_start = $(if $(ch6_warm),$(RUNS)/eqwarm_nu$(1).h5,$(RUNS)/pack_nu$(1).h5)
ch6_eq_start  = $(if $(ch6_settle),$(RUNS)/eqsettle_nu$(1).h5,$(call ch6_settle_start,$(1)))
# Options of a stage starting from $(2): a packing is thermalised, a run's last frame continued.
ch6_from      = $(if $(filter $(RUNS)/pack_nu%,$(2)),--temperature 1,--frame -1) --seed $(call ch6_seed,$(1))
ch6_gas       = --quiet --rate 0 --restitution 1 --friction 0
$(RUNS)/eqwarm_nu%.h5: $(RUNS)/pack_nu%.h5 $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear $(ch6_gas) $(call resume,gf-shear) -i $< -o $@ $(call ch6_from,$*,$<) --dt $(call ch6_dt_warm,$*) \
	  --steps $(CH6_EQ_WARMUP_STEPS) --observe-every $(CH6_EQ_OBSERVE_EVERY) --frame-every $(CH6_EQ_WARMUP_STEPS)
$(RUNS)/eqsettle_nu%.h5: $$(call ch6_settle_start,$$*) $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear $(ch6_gas) $(call resume,gf-shear) -i $< -o $@ $(call ch6_from,$*,$<) --dt $(call ch6_dt,$*) \
	  --steps $(CH6_EQ_SETTLE_STEPS) --observe-every $(CH6_EQ_OBSERVE_EVERY) --frame-every $(CH6_EQ_SETTLE_STEPS)
$(RUNS)/eq_nu%.h5: $$(call ch6_eq_start,$$*) $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear $(ch6_gas) $(call resume,gf-shear) -i $< -o $@ $(call ch6_from,$*,$<) --dt $(call ch6_dt,$*) \
	  --steps $(CH6_EQ_STEPS) --observe-every $(CH6_EQ_OBSERVE_EVERY) --frame-every $(CH6_EQ_FRAME_EVERY)

$(CH6_TABLE): $(CH6_RUNS) $(CH6_EQ_RUNS) $(STAMPS)/gf-kinetic.stamp pipelines/sizes/$(SIZE).mk | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-kinetic --quiet -o $@ --equilibrium $(subst $(space),$(comma),$(strip $(CH6_EQ_RUNS))) \
	  --from-strain $(CH6_FROM_STRAIN) --detect-transient $(CH6_KINETIC_ARGS) $(CH6_RUNS)

$(foreach k,1 2 3,$(FIGURES)/fig6_$(k).png): $(FIGURES)/fig6_%.png: $(CH6_TABLE) $(RUNS)/ch5_correlate.h5 \
                                            pipelines/plot/ch6_kinetic.py $(CH6_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch6_kinetic.py --restitutions $(CH6_PAIR_$*) $(CH6_TABLE) $(RUNS)/ch5_correlate.h5 $@

# The report's chapter-6 section (it reads ξ/ξ_el from the chapter-5 table, which ch5.mk adds).
$(FIGURES)/REPORT.md: $(CH6_TABLE) $(CH6_ANALYSIS)
REPORT_ARGS += --ch6-kinetic $(CH6_TABLE)

# ---------------------------------------------------------------- force-network model
# Thesis §6.2, Figs 6.5-6.8. Table $(RUNS)/ch6_network.h5: gf-network over the μ = 0 runs of the
# chapter-5 grid (CH6_NETWORK_NU × CH6_NETWORK_E, by default CH5_NU × CH5_E, at CH5_RATE: rows of $(RUNS)/ch5_correlate.h5, whose ξ/ξ_el
# gives the sums' limit, --correlation CH6_NETWORK_CORRELATION), the window rule of the other chapter-6 table
# (--from-strain CH6_FROM_STRAIN --detect-transient). Fig. 6.7's inset compares z at the default
# step and at half of it: half-step runs $(RUNS)/halfstep_nu<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>.h5 (the
# shear run of the same name at SHEAR_STRAIN_STEP/2, twice the steps and twice the steps between
# frames: the same strain and strain per frame) at CH6_HALFSTEP_NU × CH6_HALFSTEP_E, and a second
# table $(RUNS)/ch6_network_halfstep.h5 of them and their default-step runs, without
# --correlation (the half-step runs are no rows of ch5_correlate.h5). Figures
# $(FIGURES)/fig6_{5,6,7,8}.png: pipelines/plot/ch6_network.py. A change of gf-network's code
# redoes the two tables, these figures and the report only.
CH6_HALFSTEP_NU    ?=
CH6_HALFSTEP_E     ?=
# Fig. 6.5's run: the one nearest to this e and ν (the thesis': e = 0, ν = 0.79).
CH6_POLAR_E        ?= 0.00
CH6_POLAR_NU       ?= 0.790
# gf-network's settings beyond its defaults (e.g. --angle-bins 72).
CH6_NETWORK_ARGS   ?=
# The gf-correlate table whose ξ/ξ_el gives the sums' limit (empty: none, no right-hand sides).
CH6_NETWORK_CORRELATION ?= $(RUNS)/ch5_correlate.h5
# The grid of the force-network table: the chapter-5 μ = 0 grid unless a size narrows it.
CH6_NETWORK_NU     ?= $(CH5_NU)
CH6_NETWORK_E      ?= $(CH5_E)
CH6_NETWORK_RUNS   := $(foreach e,$(CH6_NETWORK_E),$(foreach nu,$(CH6_NETWORK_NU),\
                        $(call shear_run,$(nu),$(e),0.00,$(CH5_RATE),$(CH5_SEED))))
CH6_NETWORK_TABLE  := $(RUNS)/ch6_network.h5
halfstep_run        = $(RUNS)/halfstep_nu$(1)_e$(2)_mu$(3)_r$(4)_s$(5).h5
CH6_HALFSTEP_RUNS  := $(foreach e,$(CH6_HALFSTEP_E),$(foreach nu,$(CH6_HALFSTEP_NU),\
                        $(call halfstep_run,$(nu),$(e),0.00,$(CH5_RATE),$(CH5_SEED))))
CH6_HALFSTEP_PAIRS := $(foreach e,$(CH6_HALFSTEP_E),$(foreach nu,$(CH6_HALFSTEP_NU),\
                        $(call shear_run,$(nu),$(e),0.00,$(CH5_RATE),$(CH5_SEED))))
# No half-step runs (empty CH6_HALFSTEP_NU or _E): no second table, Fig. 6.7 without its inset.
CH6_NETWORK_HALFSTEP := $(if $(strip $(CH6_HALFSTEP_RUNS)),$(RUNS)/ch6_network_halfstep.h5)
CH6_HALFSTEP_STRAIN_STEP := $(shell awk 'BEGIN { printf "%.15g", $(SHEAR_STRAIN_STEP) / 2 }')
CH6_NETWORK_FIGURES := $(foreach k,5 6 7 8,$(FIGURES)/fig6_$(k).png)
CH6_FIGURES        += $(CH6_NETWORK_FIGURES)
CH6_NETWORK_PLOT   := pipelines/plot/ch6_network.py $(CH6_ANALYSIS)

ch6-files: $(CH6_NETWORK_FIGURES) $(CH6_NETWORK_TABLE) $(CH6_NETWORK_HALFSTEP)

# Stem "<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>", as for the shear runs (shear_arg in ch4.mk).
$(RUNS)/halfstep_nu%.h5: $(RUNS)/pack_nu$$(call shear_arg,,1,$$*)_$$(call shear_arg,,5,$$*).h5 \
                         $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear --quiet $(call resume,gf-shear) -i $< -o $@ --rate $(call shear_arg,r,4,$*) \
	  --restitution $(call shear_arg,e,2,$*) --friction $(call shear_arg,mu,3,$*) \
	  --seed $(call shear_arg,s,5,$*) --strain $(call shear_strain,$(call shear_arg,,1,$*)) \
	  --strain-step $(CH6_HALFSTEP_STRAIN_STEP) \
	  --frame-every $$((2 * $(call shear_frame_every,$(call shear_arg,,1,$*))))

$(CH6_NETWORK_TABLE): $(CH6_NETWORK_RUNS) $(CH6_NETWORK_CORRELATION) $(STAMPS)/gf-network.stamp \
                      pipelines/sizes/$(SIZE).mk | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-network --quiet -o $@ $(if $(CH6_NETWORK_CORRELATION),--correlation $(CH6_NETWORK_CORRELATION)) \
	  --from-strain $(CH6_FROM_STRAIN) --detect-transient $(CH6_NETWORK_ARGS) $(CH6_NETWORK_RUNS)
$(RUNS)/ch6_network_halfstep.h5: $(CH6_HALFSTEP_PAIRS) $(CH6_HALFSTEP_RUNS) $(STAMPS)/gf-network.stamp \
                                 pipelines/sizes/$(SIZE).mk | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-network --quiet -o $@ --from-strain $(CH6_FROM_STRAIN) --detect-transient \
	  $(CH6_NETWORK_ARGS) $(CH6_HALFSTEP_PAIRS) $(CH6_HALFSTEP_RUNS)

$(FIGURES)/fig6_5.png: $(CH6_NETWORK_TABLE) $(CH6_NETWORK_PLOT) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch6_network.py --figure 6.5 --restitution $(CH6_POLAR_E) --nu $(CH6_POLAR_NU) $< $@
$(FIGURES)/fig6_6.png $(FIGURES)/fig6_8.png: $(FIGURES)/fig6_%.png: $(CH6_NETWORK_TABLE) $(CH6_NETWORK_PLOT) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch6_network.py --figure 6.$* $< $@
$(FIGURES)/fig6_7.png: $(CH6_NETWORK_TABLE) $(CH6_NETWORK_HALFSTEP) $(CH6_NETWORK_PLOT) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch6_network.py --figure 6.7 $(if $(CH6_NETWORK_HALFSTEP),--halfstep $(CH6_NETWORK_HALFSTEP)) $< $@

$(FIGURES)/REPORT.md: $(CH6_NETWORK_TABLE) $(CH6_NETWORK_HALFSTEP)
REPORT_ARGS += --ch6-network $(CH6_NETWORK_TABLE) $(if $(CH6_NETWORK_HALFSTEP),--ch6-network-halfstep $(CH6_NETWORK_HALFSTEP))

# ---------------------------------------------------------------- STZ: non-affine motion and the law
# Thesis §6.3, Figs 6.9-6.11 (gf-stz, docs/programs/gf-stz.md; docs/method/stz.md).
# Fig. 6.9: from the last frame of the steady dense run $(CH6_STZ_PARENT) (ν = CH6_STZ_NU,
# e = CH6_STZ_E, μ = 0 at CH5_RATE: a run of the chapter-5 grid, no new long run), two gf-shear
# branches at SHEAR_STRAIN_STEP with a frame every CH6_STZ_FRAME_EVERY steps:
# $(RUNS)/d2min_forward_nu<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>.h5 at +γ̇ for strain CH6_STZ_FORWARD and
# $(RUNS)/d2min_backward_....h5 at −γ̇ for strain CH6_STZ_INTERVAL (any such name can be asked
# for: the parent is the shear run of the same stem). Maps (gf-stz d2min, neighbours within
# CH6_STZ_CUTOFF mean diameters): $(RUNS)/ch6_d2min_a.h5 strain 0 → CH6_STZ_INTERVAL, _b.h5
# CH6_STZ_FORWARD − CH6_STZ_INTERVAL → CH6_STZ_FORWARD (both frames of the forward branch), _c.h5
# 0 → CH6_STZ_FORWARD, _d.h5 0 → −CH6_STZ_INTERVAL; a, c, d take the parent's last frame as the
# reference and the branch's frame (--branch). Numbers: $(RUNS)/ch6_d2min_maps.h5
# (pipelines/analysis/d2min_maps.py: black fraction, clusters, Jaccard overlaps of a with b, c, d
# and their chance values, at CH6_STZ_THRESHOLD and over a sweep of thresholds). Figure
# $(FIGURES)/fig6_9.png.
# Fit (Figs 6.10, 6.11): $(RUNS)/ch6_stz.h5, gf-stz fit over the μ = 0 runs at every e of
# CH6_STZ_FIT_E and ν of CH6_STZ_FIT_NU and the μ = 0.4 runs at e = CH5_FRICTION_E over
# CH6_STZ_FRICTION_NU (by default the chapter-5 grids, CH5_E × CH5_NU and CH5_FRICTION_NU), the
# window rule of the other chapter-6 tables (--from-strain CH6_FROM_STRAIN --detect-transient);
# dense = ξ/ξ_el ≥ 1.25 from CH6_STZ_CORRELATION (gf-correlate's chapter-5 table), or, when that is
# empty, ν ≥ CH6_STZ_MIN_NU; the incline points (never fitted) from $(RUNS)/ch6_incline.h5, the
# incline-bulk table of the e = CH6_INCLINE_E runs at CH6_INCLINE_ANGLES_MU0 (μ = 0, from the
# incline pack, ch4_incline.mk's run rule) and CH6_INCLINE_ANGLES_MU04 (μ = 0.4, branched from
# the μ = 0 run at CH6_INCLINE_MU04_PARENT, ch4_incline.mk's branch rule): the incline settings
# (INCLINE_WIDTH, INCLINE_TIME, INCLINE_BRANCH_TIME, ...) are chapter 4's. Figures
# $(FIGURES)/fig6_10.png (μ = 0, every e) and fig6_11.png (μ = 0 and 0.4, e = 0, shear and
# incline): pipelines/plot/ch6_stz.py. A change of gf-stz's code redoes the maps, the fit, their
# analysis, Figs 6.9-6.11 and the report, never a simulation.
CH6_STZ_E           ?= 0.00
CH6_STZ_CUTOFF      ?= 2
CH6_STZ_FIT_NU      ?= $(CH5_NU)
CH6_STZ_FIT_E       ?= $(CH5_E)
CH6_STZ_FRICTION_NU ?= $(CH5_FRICTION_NU)
CH6_STZ_CORRELATION ?= $(RUNS)/ch5_correlate.h5
CH6_STZ_MIN_NU      ?=
CH6_INCLINE_E       ?= 0.00
# d2min_maps.py's default threshold when empty.
CH6_STZ_THRESHOLD   ?=
# gf-stz fit's settings beyond its defaults (e.g. --objective orthogonal).
CH6_STZ_FIT_ARGS    ?=
# d2min_maps.py's settings beyond the threshold (e.g. --gap 0.2).
CH6_STZ_MAPS_ARGS   ?=

CH6_STZ_STEM        := nu$(CH6_STZ_NU)_e$(CH6_STZ_E)_mu0.00_r$(CH5_RATE)_s$(CH5_SEED)
CH6_STZ_PARENT      := $(RUNS)/shear_$(CH6_STZ_STEM).h5
CH6_STZ_FORWARD_RUN := $(RUNS)/d2min_forward_$(CH6_STZ_STEM).h5
CH6_STZ_BACKWARD_RUN := $(RUNS)/d2min_backward_$(CH6_STZ_STEM).h5
# The frame of a branch at strain $(1) from its start: strain / (SHEAR_STRAIN_STEP ·
# CH6_STZ_FRAME_EVERY), which must be a whole number (else make stops here, naming the strain).
ch6_stz_frame = $(or $(shell awk 'BEGIN { k = ($(1)) / ($(SHEAR_STRAIN_STEP) * $(CH6_STZ_FRAME_EVERY)); \
                  r = int(k + 0.5); if (r >= 0 && k - r < 1e-6 && r - k < 1e-6) print r }'),\
                  $(error strain $(1) is not a whole number of frames of $(CH6_STZ_FRAME_EVERY) steps of \
                  $(SHEAR_STRAIN_STEP): change CH6_STZ_FRAME_EVERY))
CH6_STZ_FRAME_INTERVAL := $(call ch6_stz_frame,$(CH6_STZ_INTERVAL))
CH6_STZ_FRAME_FORWARD  := $(call ch6_stz_frame,$(CH6_STZ_FORWARD))
CH6_STZ_LATE_STRAIN    := $(shell awk 'BEGIN { printf "%.15g", $(CH6_STZ_FORWARD) - $(CH6_STZ_INTERVAL) }')
CH6_STZ_FRAME_LATE     := $(call ch6_stz_frame,$(CH6_STZ_LATE_STRAIN))
# The maps' frames come from the size file: a change there redoes them.
CH6_STZ_SIZE        := pipelines/sizes/$(SIZE).mk
CH6_D2MIN_MAPS      := $(foreach k,a b c d,$(RUNS)/ch6_d2min_$(k).h5)
CH6_D2MIN_TABLE     := $(RUNS)/ch6_d2min_maps.h5
CH6_STZ_FIT_RUNS    := $(foreach e,$(CH6_STZ_FIT_E),$(foreach nu,$(CH6_STZ_FIT_NU),\
                         $(call shear_run,$(nu),$(e),0.00,$(CH5_RATE),$(CH5_SEED)))) \
                       $(foreach nu,$(CH6_STZ_FRICTION_NU),$(call shear_run,$(nu),$(CH5_FRICTION_E),0.40,$(CH5_RATE),$(CH5_SEED)))
# Recursive, and read through secondary expansion ($$): incline_run and incline_branch are
# defined in ch4_incline.mk, included after this file.
CH6_INCLINE_RUNS     = $(foreach th,$(CH6_INCLINE_ANGLES_MU0),$(call incline_run,$(th),$(CH6_INCLINE_E),0.00,$(INCLINE_SEED))) \
                       $(foreach th,$(CH6_INCLINE_ANGLES_MU04),\
                         $(call incline_branch,$(th),$(CH6_INCLINE_E),0.40,$(INCLINE_SEED),$(CH6_INCLINE_MU04_PARENT)))
CH6_INCLINE_TABLE   := $(RUNS)/ch6_incline.h5
CH6_STZ_TABLE       := $(RUNS)/ch6_stz.h5
CH6_STZ_DENSE       := $(if $(CH6_STZ_CORRELATION),--correlation $(CH6_STZ_CORRELATION),--min-packing-fraction $(CH6_STZ_MIN_NU))
CH6_STZ_FIGURES     := $(foreach k,9 10 11,$(FIGURES)/fig6_$(k).png)
CH6_FIGURES         += $(CH6_STZ_FIGURES)
CH6_STZ_PLOT        := pipelines/plot/ch6_stz.py pipelines/analysis/d2min_maps.py $(CH6_ANALYSIS)

ch6-files: $(CH6_STZ_FIGURES) $(CH6_D2MIN_TABLE) $(CH6_STZ_TABLE)

# Stem "<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>": from the last frame of the shear run of that stem, at +γ̇
# (forward) or −γ̇ (backward).
ch6_stz_branch = $(LAUNCH) $(BIN)/gf-shear --quiet $(call resume,gf-shear) -i $< --frame -1 -o $@ --rate $(1)$(call shear_arg,r,4,$*) \
	  --restitution $(call shear_arg,e,2,$*) --friction $(call shear_arg,mu,3,$*) \
	  --seed $(call shear_arg,s,5,$*) --strain $(2) --strain-step $(SHEAR_STRAIN_STEP) \
	  --frame-every $(CH6_STZ_FRAME_EVERY)
$(RUNS)/d2min_forward_nu%.h5: $(RUNS)/shear_nu%.h5 $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(call ch6_stz_branch,,$(CH6_STZ_FORWARD))
$(RUNS)/d2min_backward_nu%.h5: $(RUNS)/shear_nu%.h5 $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(call ch6_stz_branch,-,$(CH6_STZ_INTERVAL))

ch6_d2min = $(LAUNCH) $(BIN)/gf-stz d2min --quiet --cutoff $(CH6_STZ_CUTOFF) -o $@
$(RUNS)/ch6_d2min_a.h5: $(CH6_STZ_PARENT) $(CH6_STZ_FORWARD_RUN) $(STAMPS)/gf-stz.stamp $(CH6_STZ_SIZE) | $(RUNS)/
	$(ch6_d2min) -i $(CH6_STZ_PARENT) --branch $(CH6_STZ_FORWARD_RUN) --frames -1,$(CH6_STZ_FRAME_INTERVAL)
$(RUNS)/ch6_d2min_b.h5: $(CH6_STZ_FORWARD_RUN) $(STAMPS)/gf-stz.stamp $(CH6_STZ_SIZE) | $(RUNS)/
	$(ch6_d2min) -i $(CH6_STZ_FORWARD_RUN) --frames $(CH6_STZ_FRAME_LATE),$(CH6_STZ_FRAME_FORWARD)
$(RUNS)/ch6_d2min_c.h5: $(CH6_STZ_PARENT) $(CH6_STZ_FORWARD_RUN) $(STAMPS)/gf-stz.stamp $(CH6_STZ_SIZE) | $(RUNS)/
	$(ch6_d2min) -i $(CH6_STZ_PARENT) --branch $(CH6_STZ_FORWARD_RUN) --frames -1,$(CH6_STZ_FRAME_FORWARD)
$(RUNS)/ch6_d2min_d.h5: $(CH6_STZ_PARENT) $(CH6_STZ_BACKWARD_RUN) $(STAMPS)/gf-stz.stamp $(CH6_STZ_SIZE) | $(RUNS)/
	$(ch6_d2min) -i $(CH6_STZ_PARENT) --branch $(CH6_STZ_BACKWARD_RUN) --frames -1,$(CH6_STZ_FRAME_INTERVAL)

$(CH6_D2MIN_TABLE): $(CH6_D2MIN_MAPS) pipelines/analysis/d2min_maps.py $(CH6_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/d2min_maps.py $(if $(CH6_STZ_THRESHOLD),--threshold $(CH6_STZ_THRESHOLD)) \
	  $(CH6_STZ_MAPS_ARGS) --start-strain 0,$(CH6_STZ_LATE_STRAIN),0,0 -o $@ $(CH6_D2MIN_MAPS)

$(CH6_INCLINE_TABLE): $$(CH6_INCLINE_RUNS) $$(INCLINE_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/incline_bulk.py $(INCLINE_BULK_ARGS) -o $@ $(CH6_INCLINE_RUNS)

$(CH6_STZ_TABLE): $(CH6_STZ_FIT_RUNS) $(CH6_STZ_CORRELATION) $(CH6_INCLINE_TABLE) $(STAMPS)/gf-stz.stamp \
                  pipelines/sizes/$(SIZE).mk | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-stz fit --quiet -o $@ $(CH6_STZ_DENSE) \
	  --incline $(CH6_INCLINE_TABLE) --from-strain $(CH6_FROM_STRAIN) --detect-transient $(CH6_STZ_FIT_ARGS) \
	  $(CH6_STZ_FIT_RUNS)

$(FIGURES)/fig6_9.png: $(CH6_D2MIN_TABLE) $(CH6_STZ_PLOT) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch6_stz.py --figure 6.9 $< $@
$(FIGURES)/fig6_10.png $(FIGURES)/fig6_11.png: $(FIGURES)/fig6_%.png: $(CH6_STZ_TABLE) $(CH6_STZ_PLOT) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch6_stz.py --figure 6.$* $< $@

$(FIGURES)/REPORT.md: $(CH6_STZ_TABLE) $(CH6_D2MIN_TABLE) pipelines/analysis/d2min_maps.py
REPORT_ARGS += --ch6-stz $(CH6_STZ_TABLE) --ch6-d2min $(CH6_D2MIN_TABLE)
