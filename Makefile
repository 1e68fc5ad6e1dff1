# Thin wrapper over CMake/CTest/pytest and the verification harness.
# Start with `bash scripts/setup.sh run` (or test) on a fresh machine; after that:
#   make build | run | test | verify [STUDY=name] | verify-full | format | docs
PYTHON := /usr/bin/python3
JOBS ?= 2
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1
export OMPI_MCA_rmaps_base_oversubscribe := 1
# The default case: a short, coarse capsule-in-shear run (a few minutes) with a D(t) plot.
DEFAULT_CASE ?= cases/capsule_default

.PHONY: build run test unit pytest verify verify-full format docs clean fuzz-sanitized

build:
	cmake --preset release >/dev/null
	cmake --build --preset release -j $(JOBS)

run: build
	./build/bin/efsi run $(DEFAULT_CASE) --output out/default
	$(PYTHON) verification/plot_run.py out/default

test: build
	ctest --test-dir build --output-on-failure -j $(JOBS)
	$(PYTHON) -m pytest -q reference/tests verification/tests

verify: build
	$(PYTHON) verification/run.py --tier quick $(STUDY)

# Full-tier studies that finish are kept in verification/results/ (committed) and the page
# docs/verification.md is regenerated from them, also after a single study or a failure.
verify-full: build
	$(PYTHON) verification/run.py --tier full $(STUDY); st=$$?; \
	  $(PYTHON) verification/publish.py && exit $$st

# A subset of the fuzzed bad-input test against the debug preset (ASan/UBSan, NaN-filled
# fields, FP traps): CI runs it after `make test`.
fuzz-sanitized:
	cmake --preset debug >/dev/null
	cmake --build --preset debug -j $(JOBS) --target efsi
	EFSI_FUZZ_COUNT=$${EFSI_FUZZ_COUNT:-60} $(PYTHON) $(CURDIR)/tests/integration/test_fuzz_input.py \
	  --efsi $(CURDIR)/build-debug/bin/efsi --mpiexec mpiexec --cases $(CURDIR)/cases \
	  --output $(CURDIR)/build-debug/test-output/fuzz

format:
	git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

docs: build
	./scripts/make_case_reference.sh

clean:
	rm -rf build build-debug
