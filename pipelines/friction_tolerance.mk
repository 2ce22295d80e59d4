# The tolerance study at μ = 0.4: p, s/p, T, z and the share of sliding contacts against the
# solver tolerance (results: docs/results/convergence.md, "The tolerance at μ = 0.4"). The grid is
# the file $(FRICTION_TOLERANCE) (default pipelines/sizes/friction_tolerance.mk), independent of
# SIZE; its runs go to $(FT_RUNS).
#
# Runs: $(FT_RUNS)/ft_run_n<N>_nu<ν>_e<e>_mu<μ>_dt<γ̇dt>_tol<tolerance>_s<seed>.h5, gf-shear from the
# packing $(FT_RUNS)/ft_pack_n<N>_nu<ν>_s<seed>.h5. Per run, its own tables: ft_steady_<stem>
# (steady_state.py: p, s/p, T), ft_network_<stem> (gf-network: z) and ft_sliding_<stem>
# (sliding_share.py: the share of force-bearing contacts at the Coulomb limit, over the steady
# table's window). The summary (pipelines/analysis/tolerance_study.py): friction_tolerance.h5 and
# friction_tolerance.csv, per (ν, seed, observable, tolerance) the value, its error and the
# difference from the default tolerance in combined errors, and per observable the verdict.
FRICTION_TOLERANCE ?= pipelines/sizes/friction_tolerance.mk
include $(FRICTION_TOLERANCE)
FT_RUNS ?= runs/friction_tolerance

ifneq ($(filter friction-tolerance friction-tolerance-files,$(MAKECMDGOALS)),)
ifeq ($(word 2,$(FT_TOLERANCES)),)
$(error $(FRICTION_TOLERANCE): FT_TOLERANCES needs at least two tolerances (got '$(strip $(FT_TOLERANCES))'))
endif
ifeq ($(filter $(FT_DEFAULT_TOLERANCE),$(FT_TOLERANCES)),)
$(error $(FRICTION_TOLERANCE): FT_DEFAULT_TOLERANCE ($(FT_DEFAULT_TOLERANCE)) is not one of FT_TOLERANCES)
endif
ifeq ($(strip $(FT_NU)),)
$(error $(FRICTION_TOLERANCE): FT_NU is empty)
endif
ifeq ($(strip $(FT_SEEDS)),)
$(error $(FRICTION_TOLERANCE): FT_SEEDS is empty)
endif
endif

# Run at ν = $(1), tolerance $(2), seed $(3).
ft_run = $(FT_RUNS)/ft_run_n$(FT_GRAINS)_nu$(1)_e$(FT_RESTITUTION)_mu$(FT_FRICTION)_dt$(FT_STEP)_tol$(2)_s$(3).h5
FT_SIM := $(foreach n,$(FT_NU),$(foreach t,$(FT_TOLERANCES),$(foreach s,$(FT_SEEDS),$(call ft_run,$(n),$(t),$(s)))))
FT_STEMS := $(patsubst $(FT_RUNS)/ft_run_n%.h5,%,$(FT_SIM))
FT_TABLES := $(foreach k,steady network sliding,$(FT_STEMS:%=$(FT_RUNS)/ft_$(k)_n%.h5))
FT_SUMMARY := $(FT_RUNS)/friction_tolerance.h5 $(FT_RUNS)/friction_tolerance.csv
FT_ANALYSIS := $(GRANFLOW_PY) $(FRICTION_TOLERANCE)

friction-tolerance-files: $(FT_SUMMARY)

# Stem "<N>_nu<ν>_e<e>_mu<μ>_dt<γ̇dt>_tol<tol>_s<seed>": word $(2) split at "_", prefix $(1) removed.
ft_arg = $(patsubst $(1)%,%,$(word $(2),$(subst _, ,$(3))))
# Steps between rows (frames) for a strain interval $(1) at step $(2): the nearest integer, at least 1.
ft_every = $$(awk 'BEGIN { k = int($(1) / $(2) + 0.5); print (k < 1 ? 1 : k) }')

$(FT_RUNS)/ft_pack_n%.h5: $(STAMPS)/gf-pack.stamp | $(FT_RUNS)/
	$(LAUNCH) $(BIN)/gf-pack --quiet --grains $(call ft_arg,,1,$*) --packing-fraction $(call ft_arg,nu,2,$*) \
	  --seed $(call ft_arg,s,3,$*) -o $@
$(FT_RUNS)/ft_run_n%.h5: $(FT_RUNS)/ft_pack_n$$(call ft_arg,,1,$$*)_$$(call ft_arg,,2,$$*)_$$(call ft_arg,,7,$$*).h5 \
                     $(STAMPS)/gf-shear.stamp | $(FT_RUNS)/
	$(LAUNCH) $(BIN)/gf-shear --quiet $(call resume,gf-shear) -i $< -o $@ --rate $(FT_RATE) \
	  --restitution $(call ft_arg,e,3,$*) --friction $(call ft_arg,mu,4,$*) --seed $(call ft_arg,s,7,$*) \
	  --strain $(FT_STRAIN) --strain-step $(call ft_arg,dt,5,$*) --tolerance $(call ft_arg,tol,6,$*) \
	  --observe-every $(call ft_every,$(FT_OBSERVE_STRAIN),$(call ft_arg,dt,5,$*)) \
	  --frame-every $(call ft_every,$(FT_FRAME_STRAIN),$(call ft_arg,dt,5,$*))

$(FT_RUNS)/ft_steady_n%.h5: $(FT_RUNS)/ft_run_n%.h5 pipelines/analysis/steady_state.py $(STATISTICS_STAMP) $(FT_ANALYSIS)
	$(PYTHON) pipelines/analysis/steady_state.py --from-strain $(FT_FROM_STRAIN) --detect-transient -o $@ $<
$(FT_RUNS)/ft_network_n%.h5: $(FT_RUNS)/ft_run_n%.h5 $(STAMPS)/gf-network.stamp $(FT_ANALYSIS)
	$(LAUNCH) $(BIN)/gf-network --quiet -o $@ --from-strain $(FT_FROM_STRAIN) --detect-transient $<
$(FT_RUNS)/ft_sliding_n%.h5: $(FT_RUNS)/ft_run_n%.h5 $(FT_RUNS)/ft_steady_n%.h5 pipelines/analysis/sliding_share.py \
                             $(STATISTICS_STAMP) $(FT_ANALYSIS)
	$(PYTHON) pipelines/analysis/sliding_share.py --margin $(FT_SLIDING_MARGIN) --steady $(FT_RUNS)/ft_steady_n$*.h5 \
	  -o $@ $<

$(FT_SUMMARY) &: $(FT_TABLES) pipelines/analysis/tolerance_study.py $(FT_ANALYSIS) | $(FT_RUNS)/
	$(PYTHON) pipelines/analysis/tolerance_study.py --default-tolerance $(FT_DEFAULT_TOLERANCE) --sigmas $(FT_SIGMAS) \
	  -o $(FT_RUNS)/friction_tolerance.h5 --csv $(FT_RUNS)/friction_tolerance.csv $(FT_TABLES)
