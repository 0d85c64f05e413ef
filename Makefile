# HOEmbed entry points.
#   make build   set-up (Debian packages when missing, .venv) + configure + compile
#   make demo    the main job on the built-in default model -> output/
#   make test    all tests (C++ and Python, through ctest)
#   make bench   the benchmark scripts (JSON in Benchmarks/results/)
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
PY := .venv/bin/python
SITE = $(shell $(PY) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')

.PHONY: all setup configure build demo test bench clean install

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

clean:
	rm -rf $(BUILD_DIR) install
