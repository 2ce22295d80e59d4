# Chapter 5, microstructure (thesis ch. 5, Figs 5.1-5.10); grids in pipelines/sizes/$(SIZE).mk.
#
# Runs: the chapter-4 run rule (ch4.mk), $(RUNS)/shear_nu<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>.h5, so
# runs whose parameters agree serve both chapters: every e of CH5_E at μ = 0 over CH5_NU, every
# μ of CH5_MU at e = CH5_FRICTION_E over CH5_FRICTION_NU; the reference run for ξ_el at
# CH5_REFERENCE_NU, e = CH5_REFERENCE_E.
# Fig 5.1: $(RUNS)/window_nu<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>.h5, a CH5_WINDOW_STEPS-step gf-shear
# branch from the last frame of the shear run of the same name, storing every step.
# Analyses (gf-correlate, one row per run): $(RUNS)/ch5_correlate.h5 (the sweep, with
# --reference: ξ/ξ_el, ν_bc) and $(RUNS)/ch5_clusters.h5 (the windows' contact clusters).
# Figures $(FIGURES)/fig5_<k>.png read them through python/granflow/correlation_table.py.
# ν_c(μ, e), where the steady stresses diverge: $(RUNS)/ch5_steady.h5 (steady_state.py over the
# sweep) and $(RUNS)/ch5_jamming.h5 (jamming_point.py on it, per (μ, e) group of runs at
# ν >= CH5_JAMMING_FROM_NU).
# A change of gf-correlate's code redoes the two analyses and the figures, never a run.

CH5_SWEEP_RUNS     := $(sort $(foreach e,$(CH5_E),$(foreach nu,$(CH5_NU),\
                        $(call shear_run,$(nu),$(e),0.00,$(CH5_RATE),$(CH5_SEED)))) \
                      $(foreach mu,$(CH5_MU),$(foreach nu,$(CH5_FRICTION_NU),\
                        $(call shear_run,$(nu),$(CH5_FRICTION_E),$(mu),$(CH5_RATE),$(CH5_SEED)))))
CH5_REFERENCE_RUNS := $(call shear_run,$(CH5_REFERENCE_NU),$(CH5_REFERENCE_E),0.00,$(CH5_RATE),$(CH5_SEED))
CH5_WINDOW_RUNS    := $(foreach e,$(CH5_CLUSTER_E),\
                        $(RUNS)/window_nu$(CH5_CLUSTER_NU)_e$(e)_mu0.00_r$(CH5_RATE)_s$(CH5_SEED).h5)
CH5_TABLES         := $(RUNS)/ch5_correlate.h5 $(RUNS)/ch5_clusters.h5 $(RUNS)/ch5_jamming.h5
CH5_FIGURES        := $(foreach k,1 2 3 4 5 6 7 8 9 10,$(FIGURES)/fig5_$(k).png)
CH5_ANALYSIS       := $(GRANFLOW_PY) pipelines/sizes/$(SIZE).mk
# gf-correlate's settings beyond its defaults (none at present; e.g. --blocks 10).
CH5_CORRELATE_ARGS ?=

# Every run is a row of the table, the reference too (the figures read ξ_el from its row).
CH5_ROWS           := $(sort $(CH5_SWEEP_RUNS) $(CH5_REFERENCE_RUNS))

ch5-files: $(CH5_FIGURES) $(CH5_TABLES)

# Stem "<ν>_e<e>_mu<μ>_r<γ̇>_s<seed>", as for the shear runs (shear_arg in ch4.mk).
$(RUNS)/window_nu%.h5: $(RUNS)/shear_nu%.h5 $(STAMPS)/gf-shear.stamp | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-shear --quiet $(call resume,gf-shear) -i $< --frame -1 -o $@ --rate $(call shear_arg,r,4,$*) \
	  --restitution $(call shear_arg,e,2,$*) --friction $(call shear_arg,mu,3,$*) \
	  --seed $(call shear_arg,s,5,$*) --steps $(CH5_WINDOW_STEPS) --strain-step $(SHEAR_STRAIN_STEP) \
	  --frame-every 1

$(RUNS)/ch5_correlate.h5: $(CH5_ROWS) $(STAMPS)/gf-correlate.stamp \
                          pipelines/sizes/$(SIZE).mk | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-correlate --quiet -o $@ --from-strain $(CH5_FROM_STRAIN) --detect-transient \
	  --reference $(subst $(space),$(comma),$(strip $(CH5_REFERENCE_RUNS))) $(CH5_CORRELATE_ARGS) \
	  $(CH5_ROWS)
$(RUNS)/ch5_clusters.h5: $(CH5_WINDOW_RUNS) $(STAMPS)/gf-correlate.stamp pipelines/sizes/$(SIZE).mk | $(RUNS)/
	$(LAUNCH) $(BIN)/gf-correlate --quiet -o $@ --from-strain 0 --blocks 1 --bootstrap 0 \
	  --clusters-window $(CH5_WINDOW_STEPS) $(CH5_WINDOW_RUNS)

$(RUNS)/ch5_steady.h5: $(CH5_SWEEP_RUNS) $(CH4_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/steady_state.py --from-strain $(CH5_FROM_STRAIN) --detect-transient -o $@ $(CH5_SWEEP_RUNS)
$(RUNS)/ch5_jamming.h5: $(RUNS)/ch5_steady.h5 pipelines/analysis/jamming_point.py $(CH5_ANALYSIS) | $(RUNS)/
	$(PYTHON) pipelines/analysis/jamming_point.py --from-nu $(CH5_JAMMING_FROM_NU) -o $@ $<

CH5_TABLE := $(RUNS)/ch5_correlate.h5
$(FIGURES)/fig5_1.png: $(RUNS)/ch5_clusters.h5 $(CH5_WINDOW_RUNS) pipelines/plot/ch5_clusters.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_clusters.py $< $@
$(FIGURES)/fig5_2.png: $(CH5_TABLE) pipelines/plot/ch5_correlation.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_correlation.py --restitution 0.25 --nu 0.81 --nus 0.6,0.77,0.81 $< $@
$(FIGURES)/fig5_3.png: $(CH5_TABLE) pipelines/plot/ch5_xi.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_xi.py --vary restitution $< $@
$(FIGURES)/fig5_4.png: $(CH5_TABLE) pipelines/plot/ch5_xi.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_xi.py --vary friction --restitution $(CH5_FRICTION_E) $< $@
$(FIGURES)/fig5_5.png: $(CH5_TABLE) pipelines/plot/ch5_anisotropy.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_anisotropy.py --figure 5.5 $< $@
$(FIGURES)/fig5_6.png: $(CH5_TABLE) pipelines/plot/ch5_anisotropy.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_anisotropy.py --figure 5.6 $< $@
$(FIGURES)/fig5_7.png: $(CH5_TABLE) pipelines/plot/ch5_forces.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_forces.py --figure 5.7 $< $@
$(FIGURES)/fig5_8.png: $(CH5_TABLE) pipelines/plot/ch5_forces.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_forces.py --figure 5.8 $< $@
$(FIGURES)/fig5_9.png: $(CH5_TABLE) pipelines/plot/ch5_phase.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_phase.py --figure 5.9 $< $@
$(FIGURES)/fig5_10.png: $(CH5_TABLE) pipelines/plot/ch5_phase.py $(CH5_ANALYSIS) | $(FIGURES)/
	$(PYTHON) pipelines/plot/ch5_phase.py --figure 5.10 $< $@

# The report's chapter-5 section.
$(FIGURES)/REPORT.md: $(CH5_TABLES) $(CH5_ANALYSIS)
REPORT_ARGS += --ch5-correlate $(RUNS)/ch5_correlate.h5 --ch5-clusters $(RUNS)/ch5_clusters.h5 \
               --ch5-jamming $(RUNS)/ch5_jamming.h5
