# Biperiodic packings: $(RUNS)/pack_nu<ν>_s<seed>.h5 for every ν and seed of the size.
PACKINGS := $(foreach nu,$(PACK_NU),$(foreach s,$(PACK_SEEDS),$(RUNS)/pack_nu$(nu)_s$(s).h5))
SNAPSHOT_PACKING := $(lastword $(filter %_s$(firstword $(PACK_SEEDS)).h5,$(PACKINGS)))

packings-files: $(PACKINGS)

# Stem "<ν>_s<seed>": ν is the first word, the seed the second.
$(RUNS)/pack_nu%.h5: $(STAMPS)/gf-pack.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-pack --quiet --grains $(PACK_GRAINS) \
	  --packing-fraction $(word 1,$(subst _s, ,$*)) --seed $(word 2,$(subst _s, ,$*)) -o $@
