# HOEmbed entry points.
#   make build   set-up (Debian packages when missing, .venv) + configure + compile
#   make demo    the main job on the built-in default model -> output/
#   make test    all tests (C++ and Python, through ctest)
#   make bench   the benchmark scripts (JSON in Benchmarks/results/)
#   make paraview       the ParaView 5.11 plugin (Plugin/, a separate build in build-paraview/)
#   make test-paraview  its tests (pvbatch pipeline against the VTK 9.1 build, GUI, MPI)
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
PY := .venv/bin/python
SITE = $(shell $(PY) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')

.PHONY: all setup configure build demo test bench clean install paraview test-paraview

all: build

setup:
	@bash scripts/setup.sh

$(BUILD_DIR)/build.ninja: | setup
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release \
	  -DPython3_EXECUTABLE=/usr/bin/python3 -DHOEMBED_SIMULATION_NATIVE=ON \
	  -DHOEMBED_TEST_PYTHON=$(CURDIR)/.venv/bin/python \
	  -DCMAKE_INSTALL_PREFIX=$(CURDIR)/install

configure: $(BUILD_DIR)/build.ninja

build: setup configure
	cmake --build $(BUILD_DIR) -j $(JOBS)
	@$(PY) scripts/link_package.py $(BUILD_DIR)
	@$(PY) -c "import hoembed" && echo "[build] hoembed is importable from .venv"

demo: build
	xvfb-run -a -s "-screen 0 1600x1200x24" $(PY) -m hoembed demo --output output

test: build
	cd $(BUILD_DIR) && xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure -j 1

bench: build
	xvfb-run -a $(PY) Benchmarks/run_all.py

install: build
	cmake --install $(BUILD_DIR)

PV_BUILD_DIR ?= build-paraview/build
TETGEN_SRC = $(wildcard $(CURDIR)/$(BUILD_DIR)/_deps/tetgen/tetgen-*/src)

paraview: setup
	@bash scripts/setup_paraview.sh
	cmake -S Plugin -B $(PV_BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Release \
	  -DHOEMBED_SIMULATION_NATIVE=ON \
	  -DHOEMBED_PARAVIEW_PYTHON_PREFIX=$(CURDIR)/build-paraview/python3-paraview \
	  $(if $(TETGEN_SRC),-DHOEMBED_TETGEN_SOURCE_DIR=$(firstword $(TETGEN_SRC)))
	cmake --build $(PV_BUILD_DIR) -j $(JOBS)
	@echo "[paraview] plugin in $(PV_BUILD_DIR)/lib/paraview-plugins/HOEmbed; run scripts/pvpython or scripts/pvbatch"

test-paraview: build paraview
	xvfb-run -a -s "-screen 0 1280x1024x24" $(PY) -m pytest -v Plugin/Testing

clean:
	rm -rf $(BUILD_DIR) install build-paraview
