# Quick start: `make run` and `make test`. Each installs missing Debian packages,
# configures and builds as needed.
BUILD ?= build
JOBS  ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps configure build run test bench clean

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

SST_DIR ?= $(if $(RCSIM_SST_DIR),$(RCSIM_SST_DIR),../shared/sst8086/v1)

bench: build
	$(BUILD)/rcsim bench cpu --anchor $(if $(wildcard $(SST_DIR)),--sst $(SST_DIR))
	$(BUILD)/rcsim bench serial
	$(BUILD)/rcsim bench motion
	$(BUILD)/rcsim bench system

clean:
	rm -rf $(BUILD)
