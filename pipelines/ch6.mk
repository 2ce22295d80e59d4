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
	$(LAUNCH) $(BIN)/gf-shear $(ch6_gas) -i $< -o $@ $(call ch6_from,$*,$<) --dt $(call ch6_dt_warm,$*) \
	  --steps $(CH6_EQ_WARMUP_STEPS) --observe-every $(CH6_EQ_OBSERVE_EVERY) --frame-every $(CH6_EQ_WARMUP_STEPS)
$(RUNS)/eqsettle_nu%.h5: $$(call ch6_settle_start,$$*) $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear $(ch6_gas) -i $< -o $@ $(call ch6_from,$*,$<) --dt $(call ch6_dt,$*) \
	  --steps $(CH6_EQ_SETTLE_STEPS) --observe-every $(CH6_EQ_OBSERVE_EVERY) --frame-every $(CH6_EQ_SETTLE_STEPS)
$(RUNS)/eq_nu%.h5: $$(call ch6_eq_start,$$*) $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear $(ch6_gas) -i $< -o $@ $(call ch6_from,$*,$<) --dt $(call ch6_dt,$*) \
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
	$(LAUNCH) $(BIN)/gf-shear --quiet -i $< -o $@ --rate $(call shear_arg,r,4,$*) \
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
