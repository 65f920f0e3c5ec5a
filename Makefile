# Quick start: `make run` and `make test`. Each installs missing Debian packages,
# configures and builds as needed. `make test-asan` runs the suite again under the sanitizers.
BUILD ?= build
ASAN_BUILD ?= build-asan
JOBS  ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps configure build run test test-asan bench regress regress-update clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

configure: $(BUILD)/CMakeCache.txt

build: deps configure
	cmake --build $(BUILD) -j $(JOBS)

run: build
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
