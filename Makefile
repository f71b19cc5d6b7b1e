# The two commands the README shows, `make demo` and `make test`, set up
# everything on a fresh Debian 12 machine: install the missing Debian packages
# (tools/install-deps.sh, no apt call when all are there), configure, build,
# run. Warnings are errors when CI=true.

PRESET := $(if $(filter true 1,$(CI)),ci,release)
JOBS   := $(shell nproc 2>/dev/null || echo 2)
RESULTS := build/test-results

.PHONY: all deps configure build test demo bench test-sanitize clean

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

# The default scene (the first of scenes/catalog.txt) under every integrator; a
# method that blows the orbit up is part of the lesson (exit 1 is shown, not
# fatal), bad input (exit 2) is. Then its checkpoints as a contact sheet.
DEMO_SCENE := $(shell sed -n 's/^\([a-z0-9_-]\+\).*/\1/p' scenes/catalog.txt | head -1)
demo: build
	build/plausible list
	@echo
	@for integrator in forward_euler symplectic_euler leapfrog velocity_verlet position_verlet rk4 backward_euler; do \
		build/plausible run $(DEMO_SCENE) --integrator $$integrator; status=$$?; \
		[ $$status -le 1 ] || exit $$status; echo; \
	done
	@build/plausible render $(DEMO_SCENE) --out out/demo --size 960x540 | tail -1 | sed 's/^/demo: contact sheet of $(DEMO_SCENE): /'


bench: build
	build/bench_sim --benchmark_counters_tabular=true
	build/bench_mass_spring --benchmark_counters_tabular=true
	build/bench_rigid --benchmark_counters_tabular=true
	build/bench_render --benchmark_counters_tabular=true

test-sanitize: deps
	cmake --preset sanitize >/dev/null
	cmake --build --preset sanitize -j $(JOBS)
	ctest --preset sanitize -j $(JOBS)

clean:
	rm -rf build build-sanitize
