# Quick start: `make run` and `make test`. Each installs missing Debian packages,
# configures and builds as needed: `make run` only the rcsim program and the firmware ROM it runs
# (minutes on two cores), `make test` everything, the test programs included. `make test-asan` runs the suite again under the sanitizers.
BUILD ?= build
ASAN_BUILD ?= build-asan
JOBS  ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps configure build build-rcsim run test test-asan bench regress regress-update clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

configure: $(BUILD)/CMakeCache.txt

build: deps configure
	@echo "make: building everything, the test programs included"
	cmake --build $(BUILD) -j $(JOBS)

# The rcsim target depends on the firmware ROM (comm_cpu/firmware) and on no test program
# (test layout.run_targets checks both).
build-rcsim: deps configure
	@echo "make: building rcsim and the firmware ROM (not the tests: make test builds those)"
	cmake --build $(BUILD) -j $(JOBS) --target rcsim

run: build-rcsim
	@echo "make: running scenarios/three_ports_9600.yaml (reports in $(BUILD)/run)"
	$(BUILD)/rcsim run scenarios/three_ports_9600.yaml --out $(BUILD)/run

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# AddressSanitizer + UndefinedBehaviorSanitizer (RCSIM_SANITIZE), with line tables for the reports
# (RCSIM_SANITIZE makes RelWithDebInfo -O1 -g1, see CMakeLists.txt).
# RCSIM_SANITIZE builds with -fno-sanitize-recover=undefined, so a UBSan report ends the program
# with a failure and turns its test red. (LeakSanitizer is off in the programs themselves.)
$(ASAN_BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRCSIM_SANITIZE=ON $(CMAKE_FLAGS)

test-asan: deps $(ASAN_BUILD)/CMakeCache.txt
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	cd $(ASAN_BUILD) && ctest --output-on-failure -j $(JOBS)

SST_DIR ?= $(if $(RCSIM_SST_DIR),$(RCSIM_SST_DIR),../shared/sst8086/v1)

bench: build
	$(BUILD)/rcsim bench cpu --anchor $(if $(wildcard $(SST_DIR)),--sst $(SST_DIR))
	$(BUILD)/rcsim bench serial
	$(BUILD)/rcsim bench motion
	$(BUILD)/rcsim bench system

# The regression suite (docs/regression.md): scenarios/regress/suite.yaml against its baseline;
# writes $(BUILD)/regress/compare.html, junit.xml and coverage.info (the suite's firmware coverage,
# docs/tools.md "Coverage"), exits non-zero on a regression.
regress: build
	bash scripts/regress.sh $(BUILD)/rcsim $(BUILD)/regress $(JOBS)

# Rewrites scenarios/regress/baseline/ from a fresh run of the suite (after an intended change).
regress-update: build
	bash scripts/regress.sh --update $(BUILD)/rcsim $(BUILD)/regress $(JOBS)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
