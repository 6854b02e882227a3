# The two commands of the README: `make demo` and `make test`.  Each installs what is missing,
# builds, installs the package openmmdpd into $(PYTHON)'s environment, and runs.
PYTHON ?= python3
BUILD ?= build
JOBS ?= 2
export PYTHON
# The build and the C++ tests share $(BUILD) with pip's build of the package (one build, not two).
export CMAKE_GENERATOR ?= Unix Makefiles
export CMAKE_BUILD_PARALLEL_LEVEL := $(JOBS)

.PHONY: all deps build install test test-cpp test-python test-installed test-cpp-install test-sanitize docs demo study-full transport claims bench bench-gpu clean

all: build

deps:
	@bash tools/install-dependencies.sh

# Builds (incrementally, in $(BUILD), with the C++ tests and examples) and installs openmmdpd into
# $(PYTHON)'s environment with pip, against the OpenMM that environment has, then the studies
# (openmmdpd_studies, pure Python, from studies/).  Every make reinstalls both from this tree, so the
# installed copies are never older than the sources.
build: deps
	@echo "Building and installing openmmdpd and openmmdpd-studies into $$($(PYTHON) -c 'import sys; print(sys.prefix)') (log: $(BUILD).install.log)"
	@$(PYTHON) -m pip install --no-deps --no-build-isolation --force-reinstall --no-index -v . \
		-Cbuild-dir=$(BUILD) \
		-Ccmake.define.OPENMMDPD_BUILD_TESTS=ON -Ccmake.define.OPENMMDPD_BUILD_EXAMPLES=ON \
		> $(BUILD).install.log 2>&1 || (tail -n 60 $(BUILD).install.log; exit 1)
	@$(PYTHON) -m pip install --no-deps --no-build-isolation --force-reinstall --no-index -v ./studies \
		>> $(BUILD).install.log 2>&1 || (tail -n 60 $(BUILD).install.log; exit 1)
	@cd / && $(PYTHON) -c "import openmmdpd, openmmdpd_studies; print('Installed', openmmdpd.__file__, 'and', openmmdpd_studies.__file__)"

install: build

test-cpp: build
	ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS)

test-python: build
	$(PYTHON) -m pytest tests/python -q --durations=12

test: test-cpp test-python

# The package as a user gets it: imported from outside the clone, and the README's example run there.
test-installed: build
	@bash tools/check-installed.sh

# The C++ API as a user gets it: the README's C++ program and examples/cpp built outside the clone with
# find_package(OpenMMDPD) against the installed package, and run.
test-cpp-install: build
	@bash tools/check-cpp-install.sh

# The documentation: Doxygen reads the public C++ headers into $(DOCS_BUILD)/doxygen, then Sphinx (autodoc
# on the INSTALLED openmmdpd, Breathe on Doxygen's XML) writes $(DOCS_BUILD)/html; warnings are errors in
# both.  It builds and installs no openmmdpd: it documents the one $(PYTHON) imports (run make first).
DOCS_BUILD ?= $(BUILD)/docs
docs: deps
	@mkdir -p $(DOCS_BUILD)/doxygen
	OPENMMDPD_DOXYGEN_OUTPUT=$(abspath $(DOCS_BUILD)/doxygen) doxygen docs/Doxyfile
	OPENMMDPD_DOXYGEN_XML=$(abspath $(DOCS_BUILD)/doxygen/xml) $(PYTHON) -m sphinx -W --keep-going -q -b html docs $(DOCS_BUILD)/html
	@echo "Documentation: $(DOCS_BUILD)/html/index.html"

# The C++ suite under AddressSanitizer + UndefinedBehaviorSanitizer, in its own build folder (no Python
# package, no examples).  OpenMM itself is not instrumented; leaks are not checked (OpenMM's plugin
# registry is never freed by design).  Any sanitizer report fails the run.
SANITIZE_BUILD ?= build-sanitize
SANITIZE_FLAGS = -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=all
test-sanitize: deps
	@cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOPENMMDPD_BUILD_PYTHON=OFF -DOPENMMDPD_BUILD_EXAMPLES=OFF \
	    -DCMAKE_CXX_FLAGS="$(SANITIZE_FLAGS)" -DCMAKE_EXE_LINKER_FLAGS="$(SANITIZE_FLAGS)" -DCMAKE_SHARED_LINKER_FLAGS="$(SANITIZE_FLAGS)" \
	    -DPython_EXECUTABLE=$$(command -v $(PYTHON)) > $(SANITIZE_BUILD).configure.log 2>&1 || (cat $(SANITIZE_BUILD).configure.log; exit 1)
	@cmake --build $(SANITIZE_BUILD) -j$(JOBS)
	ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	    ctest --test-dir $(SANITIZE_BUILD) --output-on-failure -j$(JOBS)

SCENES = examples/scenes/soft_fluid_gamma4.5.toml examples/scenes/soft_fluid_gamma40.5.toml \
         examples/scenes/soft_fluid_gamma200.toml examples/scenes/soft_fluid_gamma450.toml \
         examples/scenes/lj_fluid_gamma4.5.toml examples/scenes/sheared_soft_fluid_gamma450.toml
BUDGET ?= reduced
REPORT ?= demo-output

# The main job: the per-scheme table of the standard scene, then the efficiency study (reduced budget:
# about 10 minutes on 2 cores) with its report in $(REPORT)/.
demo: build
	$(PYTHON) examples/demo.py
	$(PYTHON) -m openmmdpd_studies.efficiency $(SCENES) --budget $(BUDGET) --out $(REPORT)

# The paper's full protocol (1000 time units, 10 runs, 15% step-size increments): days on 2 cores.
study-full: build
	$(PYTHON) -m openmmdpd_studies.efficiency $(SCENES) --budget full --out study-full

# The paper's claims about its other methods (BAOAB, BAOOAB, S1-OU; Shang 2021 sec. 2.3 and after Figure 4):
# the claims table with error bars and verdicts in claims-report/report.md, and PAdL's dynamics against DPD's
# (claim 9) in claims-report/padl-dynamics/report.md; about 20 minutes on 2 cores.
claims: build
	$(PYTHON) -m openmmdpd_studies.efficiency examples/scenes/soft_fluid_gamma4.5.toml examples/scenes/soft_fluid_gamma200.toml \
		examples/scenes/soft_fluid_gamma450.toml --budget claims --methods ABOBA BAOAB BAOOAB S1 S1-OU PAdL --workers 2 --out claims-report
	$(PYTHON) -m openmmdpd_studies.padl_dynamics --workers 2 --out claims-report/padl-dynamics

# The transport study (NEMD and matched Norton, friction and system-size scans): about 9 minutes on 2 cores
# at the reduced budget.
transport: build
	$(PYTHON) -m openmmdpd_studies.transport examples/scenes/transport_lj_fluid.toml --budget $(BUDGET) --out transport-report

bench: build
	$(PYTHON) benchmarks/bench.py --out benchmarks/bench-results.md

# The GPU platforms (CUDA, OpenCL) against OpenMM's own DPDIntegrator; on OpenCL on the CPU (pocl) the two
# smallest sizes only.  Also runnable alone: python benchmarks/bench_gpu.py --help.
bench-gpu: build
	$(PYTHON) benchmarks/bench_gpu.py --out benchmarks/bench-gpu-results.md

clean:
	rm -rf $(BUILD) $(BUILD).install.log $(SANITIZE_BUILD) $(SANITIZE_BUILD).configure.log
