# The two commands of the README: `make demo` and `make test`.  Each installs what is missing,
# builds, and runs.
PYTHON ?= python3
BUILD ?= build
JOBS ?= 2
export PYTHONPATH := $(CURDIR)/$(BUILD)/python$(if $(PYTHONPATH),:$(PYTHONPATH))
export PYTHON

.PHONY: all deps build test test-cpp test-python demo bench clean

all: build

deps:
	@bash tools/install-dependencies.sh

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$$(command -v $(PYTHON)) > $(BUILD).configure.log 2>&1 || (cat $(BUILD).configure.log; exit 1)
	@cmake --build $(BUILD) -j$(JOBS)

test-cpp: build
	ctest --test-dir $(BUILD) --output-on-failure -j$(JOBS)

test-python: build
	$(PYTHON) -m pytest tests/python -q

test: test-cpp test-python

demo: build
	$(PYTHON) examples/demo.py

clean:
	rm -rf $(BUILD) $(BUILD).configure.log
