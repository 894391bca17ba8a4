# motionsig — the two commands of the README are `make demo` and `make test`.
# Everything runs inside .venv, created on first use with Python >= 3.11.

PYTHON ?= $(shell command -v python3.11 || command -v python3)
VENV   := .venv
BIN    := $(VENV)/bin
HASH   := $(shell cat pyproject.toml | cksum | cut -d' ' -f1)
RUN_STAMP := $(VENV)/.stamp-run-$(HASH)
DEV_STAMP := $(VENV)/.stamp-dev-$(HASH)
DOCS_STAMP := $(VENV)/.stamp-docs-$(HASH)
# Material for MkDocs prints an end-of-life notice on every build (May 2027); what a move to its successor
# would take is noted in docs/hooks/README.md. The notice asks nothing of this build.
export NO_MKDOCS_2_WARNING := 1
MATHJAX   := docs/javascripts/mathjax/tex-svg.js
OUT    ?= out

.PHONY: demo demo-compare test preflight lint pytest docs browser-check serve clean bench reproduce

$(BIN)/python:
	$(PYTHON) -c 'import sys; assert sys.version_info >= (3, 11), "motionsig needs Python >= 3.11"'
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(RUN_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e .
	touch $@

$(DEV_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e '.[test,docs]'
	touch $@ $(RUN_STAMP) $(DOCS_STAMP)

$(DOCS_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e '.[docs]'
	touch $@ $(RUN_STAMP)

## demo: the main job — simulate a vehicle carrying a mode signature and detect its mode (the mode-signature paper),
## then one example of every command. A short story on the terminal (what ran, its one-line result on stderr,
## where the output went); the full tables in $(OUT)/*.csv, the figures in $(OUT)/*.png.
demo: $(RUN_STAMP)
	@mkdir -p $(OUT)
	@echo '== motionsig demo: 14 runs, each with what it does and its one-line result; full tables in $(OUT)/*.csv, figures in $(OUT)/*.png'
	@echo '-- 1. simulate | detect: a vehicle in mode 2, code phase 5 chips (R = 1e-3); LMP bank of 187 Kalman filters -> $(OUT)/detect.csv, fig2.png, fig3.png'
	@$(BIN)/motionsig simulate --mode 2 --tau-chips 5 --R 1e-3 --plot $(OUT)/fig2.png | $(BIN)/motionsig detect --plot $(OUT)/fig3.png -o $(OUT)/detect.csv
	@echo '-- 2. encode table1: Table I of the mode-signature paper, printed vs corrected Gold codes -> $(OUT)/table1_errata.csv'
	@$(BIN)/motionsig encode table1 --view errata -o $(OUT)/table1_errata.csv
	@echo '-- 3. encode gold | correlations: the 33-member Gold family of the preferred pair 45/75 -> $(OUT)/gold_correlations.csv'
	@$(BIN)/motionsig encode gold --poly1 45 --poly2 75 --all | $(BIN)/motionsig encode correlations - --view values -o $(OUT)/gold_correlations.csv
	@echo '-- 4. detect --montecarlo: Fig 4, 10 trials per cell (make reproduce runs 50) -> $(OUT)/fig4.csv, fig4.png'
	@$(BIN)/motionsig detect --montecarlo --trials 10 --fr-list 0.01 --plot $(OUT)/fig4.png -o $(OUT)/fig4.csv
	@echo '-- 5. detect --method fft: the FFT fast path (Q_a = 0), Fig 4 grid, 200 trials per cell -> $(OUT)/fig4_fft.csv'
	@$(BIN)/motionsig detect --montecarlo --method fft --trials 200 --fr-list 0.01 --horizons 5,10,20,40 -o $(OUT)/fig4_fft.csv
	@echo '-- 6. detect --calibrate: the threshold for P_FA = 0.01 (2000 null trials per cell), P_D at it, ROC -> $(OUT)/calibration.csv, roc.png'
	@$(BIN)/motionsig detect --calibrate --method fft --pfa 0.01 --trials 200 --R-list 1,10 --horizons 5,10,20 --plot $(OUT)/roc.png -o $(OUT)/calibration.csv
	@echo '-- 7. simulate --example 2d | detect: a planar vehicle seen by a radar (Fig 7 setting); 187 unscented filters -> $(OUT)/radar_detect.csv, radar.png'
	@$(BIN)/motionsig simulate --example 2d --mode 3 --tau-chips 7 --duration 30 --plot $(OUT)/radar.png | $(BIN)/motionsig detect --horizons 10,30 -o $(OUT)/radar_detect.csv
	@echo '-- 8. jam-bound table: ATC-10 Table 2.1, jammer ERP that mislocates 10 % of the aircraft -> $(OUT)/table2_1.csv'
	@$(BIN)/motionsig jam-bound table --which 2.1 -o $(OUT)/table2_1.csv
	@echo '-- 9. jam-bound curves: ATC-10 Fig 2.16, ambiguous-detection bound -> $(OUT)/fig2_16.csv, fig2_16.png'
	@$(BIN)/motionsig jam-bound curves --figure 2.16 --plot $(OUT)/fig2_16.png -o $(OUT)/fig2_16.csv
	@echo '-- 10. track-sat table: ATC-10 Table 4.3, position error with clock tracking -> $(OUT)/table4_3.csv'
	@$(BIN)/motionsig track-sat table --which 4.3 -o $(OUT)/table4_3.csv
	@echo '-- 11. track-sat rms: ATC-10 Fig 4.3, RMS error through a 60 s three-satellite outage -> $(OUT)/fig4_3.csv, fig4_3.png'
	@$(BIN)/motionsig track-sat rms --figure 4.3 --plot $(OUT)/fig4_3.png -o $(OUT)/fig4_3.csv
	@echo '-- 12. slrt: track existence from four radars in clutter (Govaers), CKF / FKF / LKF and Wald decisions, 20 runs -> $(OUT)/slrt_decisions.csv, slrt.png'
	@$(BIN)/motionsig slrt --view decisions --runs 20 --plot $(OUT)/slrt.png -o $(OUT)/slrt_decisions.csv
	@echo '-- 13. maneuver: a target turning twice (Yao, Teng & Wu); IMM, GLR, MLR and a CV filter, 100 runs -> $(OUT)/maneuver_summary.csv, maneuver.png, maneuver_compare.png'
	@$(BIN)/motionsig maneuver --method all --view summary --runs 100 --plot $(OUT)/maneuver.png --plot-compare $(OUT)/maneuver_compare.png -o $(OUT)/maneuver_summary.csv
	@echo '-- 14. mac-roc: ATC-10 Fig 3.3, ROC bounds under multiple-access noise with the exact ROC -> $(OUT)/fig3_3.csv, fig3_3.png, mac_report.csv'
	@$(BIN)/motionsig mac-roc bounds --figure 3.3 --exact --theta 0.02:0.98:0.02 --plot $(OUT)/fig3_3.png -o $(OUT)/fig3_3.csv
	@$(BIN)/motionsig mac-roc report -o $(OUT)/mac_report.csv
	@echo '== done. Tables: $(OUT)/*.csv (each headed by # lines with every parameter). Figures: $(OUT)/*.png.'
	@echo '   Next: source .venv/bin/activate, then motionsig --help (or ./motionsig --help without activating);'
	@echo '   make docs builds the documentation site into site/ (open site/index.html).'

## demo-compare: every make demo output of this tree against those of commit REV (default HEAD)
REV ?= HEAD
demo-compare: $(RUN_STAMP)
	$(BIN)/python scripts/demo_outputs.py against $(REV)

## test: ruff, pytest, strict docs build (executes the notebooks), browser check of the built site
## (checks for its system packages, chromium and npm, before anything else)
test: preflight $(DEV_STAMP) $(MATHJAX)
	$(BIN)/ruff check .
	$(BIN)/python -m pytest
	$(BIN)/mkdocs build --strict
	$(BIN)/python scripts/browser_check.py site

preflight:
	@missing=""; \
	for c in chromium npm; do command -v $$c >/dev/null 2>&1 || missing="$$missing $$c"; done; \
	if [ -n "$$missing" ]; then \
	  echo "make test: missing system packages:$$missing (the docs build needs npm, the browser check chromium)."; \
	  echo "  install them with: sudo apt-get update && sudo apt-get install -y$$missing   (or run: bash .ci/run)"; \
	  exit 2; \
	fi

lint: $(DEV_STAMP)
	$(BIN)/ruff check .

pytest: $(DEV_STAMP)
	$(BIN)/python -m pytest

docs: $(DOCS_STAMP) $(MATHJAX)
	$(BIN)/mkdocs build --strict

browser-check: docs $(DEV_STAMP)
	$(BIN)/python scripts/browser_check.py site

serve: $(DOCS_STAMP) $(MATHJAX)
	$(BIN)/mkdocs serve -a 127.0.0.1:8000

# MathJax 3 comes from the npm registry at build time (no CDN in the built site).
$(MATHJAX): scripts/fetch_mathjax.sh
	bash scripts/fetch_mathjax.sh $@

## bench: side-by-side timing of the LMP filter banks, the FFT path and the IMM against FilterPy (and, on a real ADS-B
## feed, against FilterPy and Stone Soup), and of the
## Monte Carlo engine (1 worker, 2 workers, Dask) and the start-up of the command line; results in benchmarks/results/, copied with a figure to
## docs/performance/ and the Performance page (not part of the tests; ~12 minutes on 2 cores). Where JAX imports
## (optional: pip install -e '.[bench-jax]'), bench_kf_bank.py also times the bank against JAX on one core; without it, that part is skipped
bench: $(DEV_STAMP)
	$(BIN)/python -m pip install -q -e '.[bench,dask]'
	$(BIN)/python benchmarks/bench_kf_bank.py
	$(BIN)/python benchmarks/bench_ukf_bank.py
	$(BIN)/python benchmarks/bench_ukf_history.py
	$(BIN)/python benchmarks/bench_imm.py
	$(BIN)/python benchmarks/bench_tracks.py
	$(BIN)/python benchmarks/bench_feed_memory.py
	$(BIN)/python benchmarks/bench_slrt.py
	$(BIN)/python benchmarks/bench_fft.py
	$(BIN)/python benchmarks/bench_radar_fast.py
	$(BIN)/python benchmarks/bench_engine.py
	$(BIN)/python benchmarks/bench_startup.py
	$(BIN)/python scripts/bench_report.py

## reproduce: every table and figure of the mode-signature paper (results/mode_signature/), the SLRT slides (results/slrt/), the EBPSK paper (results/maneuver/), ATC-10 §2 (results/atc10_jamming/), §3 (results/atc10_mac/) and §4 (results/atc10_tracking/)
reproduce: $(RUN_STAMP)
	$(BIN)/python scripts/reproduce_mode_signature.py
	$(BIN)/python scripts/reproduce_lmp_search.py
	$(BIN)/python scripts/reproduce_baseline_roc.py
	@mkdir -p results/slrt
	$(BIN)/motionsig slrt --plot results/slrt/slrt.png --plot-scan results/slrt/scan.png -o results/slrt/slrt_curves.csv -q
	$(BIN)/motionsig slrt --view decisions --runs 200 -o results/slrt/slrt_decisions.csv -q
	$(BIN)/motionsig slrt --view study --target-motion cv,agile --methods ckf,fkf,fkf-feedback,lkf,ldf,naive --runs 1000 --max-minutes 30 -o results/slrt/slrt_study.csv -q
	$(BIN)/motionsig slrt --view study --target-motion agile --filter-q 600 --methods ckf,fkf,fkf-feedback,lkf,ldf,naive --runs 1000 --max-minutes 30 -o results/slrt/slrt_study_agile_q600.csv -q
	$(BIN)/motionsig slrt --view matched --methods ckf,fkf,fkf-feedback,lkf,ldf --runs 1000 --max-minutes 30 -o results/slrt/slrt_matched.csv -q
	$(BIN)/motionsig slrt --view oc --methods ckf,fkf,fkf-feedback,lkf,ldf --runs 1000 --max-minutes 30 -o results/slrt/slrt_oc.csv -q
	$(BIN)/python scripts/check_slrt_long_run.py | tee results/slrt/long_run.txt
	@mkdir -p results/maneuver
	for p in literal turn90; do \
	  $(BIN)/motionsig maneuver --preset $$p --method all --plot results/maneuver/figs2-4_$$p.png --plot-compare results/maneuver/compare_$$p.png -o results/maneuver/scans_$$p.csv -q && \
	  $(BIN)/motionsig maneuver --preset $$p --method all --view summary -o results/maneuver/summary_$$p.csv -q && \
	  $(BIN)/motionsig maneuver --preset $$p --method glr,mlr --view events -o results/maneuver/events_$$p.csv -q || exit 1; \
	done
	$(BIN)/python scripts/reproduce_atc10_jamming.py
	$(BIN)/python scripts/reproduce_atc10_mac.py
	$(BIN)/python scripts/reproduce_atc10_tracking.py

clean:
	rm -rf site $(OUT) .pytest_cache .ruff_cache docs/javascripts/mathjax
