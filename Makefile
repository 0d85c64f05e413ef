# HOEmbed entry points.
#   make build   set-up (Debian packages when missing, .venv) + configure + compile
#   make demo    the main job on the built-in default model -> output/
#   make test    all tests: C++ and Python through ctest, the sanitizer suite and the
#                ParaView plugin's tests (what CI runs)
#   make test-sanitize  the C++ tests and a subset of the Python tests on an
#                AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/, TetGen
#                included); part of `make test`. Suppressions: Testing/sanitizers/
#   make format  the house style (clang-format, ruff) on every tracked source file
#   make bench   the benchmark scripts (JSON in Benchmarks/results/)
#   make paraview       the ParaView 5.11 plugin (Plugin/, a separate build in build-paraview/)
#   make test-paraview  its tests (pvbatch pipeline against the VTK 9.1 build, GUI, MPI)
#   make wheel   the self-contained binary wheels for pyvista users in dist/ (pyproject.toml,
#                scripts/build_wheel.sh: pip wheel + auditwheel repair, a manylinux tag):
#                one per CPython of WHEEL_PYTHONS (3.10, 3.11; 3.12: the abi3 wheel for
#                every 3.12+)
#   make test-pip       those wheels installed with --only-binary=:all: in fresh venvs of
#                the cells of PIP_MATRIX (CPython:VTK:pyvista), against the VTK build's
#                outputs, and the bitwise stepper test build (scripts/test_pip.sh); part
#                of `make test`. make test-pip-vtk95: one cell on VTK 9.5.2
BUILD_DIR ?= build
JOBS ?= $(shell nproc)
PY := .venv/bin/python
# pyenv's CPythons (scripts/build_wheel.sh finds them; else python3.X on PATH)
WHEEL_PYTHONS ?= 3.10 3.11 3.12
# the issue's two cells, and the oldest VTK and pyvista the wheel accepts (numpy 1.x, as
# they were built for)
PIP_MATRIX ?= 3.11:9.4.2:0.46.5 3.13:newest:newest 3.10:9.3.1:0.42.3:numpy<2
SITE = $(shell $(PY) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')

ASAN_DIR ?= build-asan
# -O1 -g1: ASan's recommended optimisation, line tables for the reports; quicker to
# compile than -O2 -g (a first -O2 -g build spent over 10 minutes on tetgen.cxx alone).
SAN_FLAGS := -fsanitize=address,undefined -fno-omit-frame-pointer
# Sanitized Python tests: the ones that drive every filter and the CLI on small inputs
# (the mesher's and the embedding's full Python suites run unsanitized only: their real-
# mesh cases take minutes under ASan; the C++ tests cover those filters sanitized).
SAN_PY_TESTS ?= py\.(test_bad_input|test_fuzz_surfaces|test_series|test_cli|test_simulation|test_transfer|test_package)$$

.PHONY: format all setup configure build demo test test-unsanitized test-sanitize build-sanitize bench clean install paraview test-paraview wheel test-pip test-pip-vtk95

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
	xvfb-run -a -s "-screen 0 1600x1200x24 -noreset" $(PY) -m hoembed demo --output output

test: test-unsanitized test-sanitize test-paraview test-pip

test-unsanitized: build
	cd $(BUILD_DIR) && xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j 1

# libstdc++ is preloaded with the ASan runtime: Python does not link it, and ASan's
# __cxa_throw interceptor must find it at start-up, or the first C++ exception (TetGen
# reports failures by throwing) aborts with "CHECK failed: real___cxa_throw".
$(ASAN_DIR)/build.ninja: Makefile | setup
	cmake -S . -B $(ASAN_DIR) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
	  -DCMAKE_C_FLAGS="$(SAN_FLAGS)" -DCMAKE_CXX_FLAGS="$(SAN_FLAGS)" \
	  -DCMAKE_EXE_LINKER_FLAGS="$(SAN_FLAGS)" -DCMAKE_SHARED_LINKER_FLAGS="$(SAN_FLAGS)" \
	  -DPython3_EXECUTABLE=/usr/bin/python3 -DHOEMBED_BUILD_BENCHMARKS=OFF \
	  -DHOEMBED_TEST_PYTHON=$(CURDIR)/.venv/bin/python \
	  -DHOEMBED_TEST_PYTHON_PRELOAD="$$(gcc -print-file-name=libasan.so):$$(gcc -print-file-name=libstdc++.so)" \
	  -DCMAKE_INSTALL_PREFIX=$(CURDIR)/$(ASAN_DIR)/install

build-sanitize: setup $(ASAN_DIR)/build.ninja
	cmake --build $(ASAN_DIR) -j $(JOBS)

test-sanitize: build-sanitize
	bash scripts/test_sanitize.sh $(ASAN_DIR) '$(SAN_PY_TESTS)'

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

# Xvfb with -noreset: without it the server resets when its last client leaves, and a
# process connecting at that moment is refused ("bad X server connection": 7 of 35 MPI
# display runs before).
test-paraview: build paraview
	xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" $(PY) -m pytest -v Plugin/Testing

# setup: the Debian packages (compiler, CMake, Eigen, CGAL, GMP, MPFR); the TetGen sources
# of `make build`, when there, serve the wheel too (else the wheel's build fetches them)
wheel: setup
	bash scripts/build_wheel.sh $(WHEEL_PYTHONS)

test-pip: build wheel
	bash scripts/test_pip.sh $(foreach c,$(PIP_MATRIX),'$(c)')

test-pip-vtk95: build wheel
	bash scripts/test_pip.sh 3.11:9.5.2:newest

format: setup
	bash scripts/format.sh

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR) install build-paraview build-pip dist
