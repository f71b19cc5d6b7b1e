# The two commands the README shows, `make demo` and `make test`, set up
# everything on a fresh Debian 12 machine: install the missing Debian packages
# (tools/install-deps.sh, no apt call when all are there), configure, build,
# run. Warnings are errors when CI=true.

PRESET := $(if $(filter true 1,$(CI)),ci,release)
JOBS   := $(shell nproc 2>/dev/null || echo 2)
RESULTS := build/test-results

.PHONY: all deps configure build test test-extra demo bench test-sanitize check-clang fuzz sweep clean

all: build

deps:
	@sh tools/install-deps.sh

configure: deps
	cmake --preset $(PRESET) >/dev/null

build: configure
	cmake --build --preset $(PRESET) -j $(JOBS)

test: build
	@rm -rf $(RESULTS)
	ctest --preset $(PRESET) -j $(JOBS)
	@echo
	@echo "Fitted orders of convergence (least squares over 6 step sizes, log-log):"
	@cat $(RESULTS)/orders-*.txt

# What make test leaves out to stay within 10 minutes on 2 cores: the checks
# as other x86-64 CPUs under qemu-user and the fuzz smoke run (it builds its
# own clang fuzzers). CI runs it after make test (.ci/run).
test-extra: build
	ctest --preset $(PRESET)-extra -j $(JOBS)

# The default demo: the scenes listed, then the showcase (ragdolls, cloth, rope
# and a fountain in one scene, the first of scenes/catalog.txt) as an MP4 and a
# contact sheet, and the classic energy-drift lesson (forward vs symplectic
# Euler vs Verlet on the orbit) side by side. The video command prints what
# physics and rendering cost per frame; on a terminal it shows a progress bar.
DEMO_SCENE := $(shell sed -n 's/^\([a-z0-9_-]\+\).*/\1/p' scenes/catalog.txt | head -1)
demo: build
	build/plausible list
	@echo
	@mkdir -p out
	build/plausible video $(DEMO_SCENE) -o out/$(DEMO_SCENE).mp4
	@build/plausible render $(DEMO_SCENE) --out out --size 960x540 | tail -1 | sed 's/^/demo: contact sheet: /'
	build/plausible video orbit --compare forward_euler,symplectic_euler,velocity_verlet -o out/orbit-compare.mp4
	@echo
	@echo "demo: out/$(DEMO_SCENE).mp4, out/$(DEMO_SCENE)_sheet.png, out/orbit-compare.mp4"
	@echo "demo: try the same scene in a window: build/plausible view $(DEMO_SCENE)"

bench: build
	build/bench_sim --benchmark_counters_tabular=true --benchmark_repetitions=3 --benchmark_enable_random_interleaving=true
	build/bench_mass_spring --benchmark_counters_tabular=true
	build/bench_rigid --benchmark_counters_tabular=true
	build/bench_render --benchmark_counters_tabular=true
	build/bench_video --benchmark_counters_tabular=true

test-sanitize: deps
	cmake --preset sanitize >/dev/null
	cmake --build --preset sanitize -j $(JOBS)
	ctest --preset sanitize -j $(JOBS)

# The second compiler (issue 19): the whole project built with clang in
# build-clang/ (warnings as errors under CI=true, the same determinism flags),
# then every golden check, state hashes and images, against the goldens that
# gcc's build made. .ci/run runs it once, after make test.
check-clang: deps
	cmake --preset clang >/dev/null
	cmake --build --preset clang -j $(JOBS)
	build-clang/plausible check --report build-clang/check

# The fuzzers (tools/fuzz: the scene loader, the recording reader, the
# viewer's input scripts): built with clang, ASan and UBSan into build-fuzz/,
# run for FUZZ_SECONDS in all on their seeds; what they find lands in
# build-fuzz/findings/. make test runs them for 45 s (the test fuzz.smoke, in
# build/fuzz).
FUZZ_SECONDS := 600
fuzz: deps
	FUZZ_JOBS=$(JOBS) sh tools/fuzz/run.sh $(FUZZ_SECONDS) build-fuzz

# The mutation sweep in full (tests/robustness/mutation_sweep.cpp): every
# numeric value of every shipped scene replaced by extremes and scaled, 30
# frames each in a forked child under CPU and memory limits; make test runs
# every 7th variant (robustness.mutation_sweep). Findings are printed with
# the scene and the --set that makes them.
sweep: build
	build/mutation_sweep scenes --every 1 --jobs $(JOBS)

clean:
	rm -rf build build-sanitize build-clang build-fuzz
