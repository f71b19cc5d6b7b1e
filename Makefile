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

demo: build
	build/plausible list
	@echo
	@for integrator in forward_euler symplectic_euler leapfrog velocity_verlet position_verlet rk4 backward_euler; do \
		build/plausible run orbit --integrator $$integrator || exit $$?; \
	done

bench: build
	build/bench_sim --benchmark_counters_tabular=true
	build/bench_render --benchmark_counters_tabular=true

test-sanitize: deps
	cmake --preset sanitize >/dev/null
	cmake --build --preset sanitize -j $(JOBS)
	ctest --preset sanitize -j $(JOBS)

clean:
	rm -rf build build-sanitize
