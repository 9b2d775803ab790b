# railbrake: `make demo` builds, installs and runs the main job; `make test` runs every test.
# Both create .venv when it is missing and install the package (which compiles the C core).

PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
BUILD ?= build
JOBS ?= 2
OUT ?= out
SOURCES := pyproject.toml CMakeLists.txt $(shell find core src -type f -not -name '*.pyc' 2>/dev/null)

.PHONY: demo test test-long install docs docs-fast ctest ctest-sanitize pytest pytest-sanitize bench validate clean fuzz \
        fuzz-fmi fuzz-frames fuzz-python wine wheel wheel-test browser system-packages

$(VENV)/.installed: $(SOURCES)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q '.[test,docs,fmu]'
	touch $@

install: $(VENV)/.installed

demo: install
	$(VENV)/bin/railbrake demo --out $(OUT)

test: ctest ctest-sanitize docs-fast pytest pytest-sanitize

# The documentation site (docs/conf.py: Sphinx + MyST-NB): every page's code cells run at build and
# the figures in the prose come from them; executions are cached in $(BUILD)/docs/jupyter_cache under
# a digest of the installed package, so an unchanged page of unchanged code is not run again, and a
# model change re-measures every page. Warnings are errors. Offline: everything is in .venv.
# docs-fast (part of `make test`): the quick executed pages and the API reference only.
SPHINX := $(VENV)/bin/sphinx-build -q -W --keep-going -b html

docs: install
	$(SPHINX) docs $(BUILD)/docs/html
	@echo "docs: $(BUILD)/docs/html/index.html"

docs-fast: install
	$(SPHINX) -t fast -d $(BUILD)/docs-fast/doctrees docs $(BUILD)/docs-fast/html

# The C core on its own, as a downstream C user (FMU, HIL target) builds it.
ctest:
	cmake -S core -B $(BUILD)/core -DCMAKE_BUILD_TYPE=Debug >/dev/null
	cmake --build $(BUILD)/core -j$(JOBS)
	ctest --test-dir $(BUILD)/core --output-on-failure -j$(JOBS)

# -O1: AddressSanitizer's own advice for tolerable speed (the Python tests run whole stops on this
# library); -g and the frame pointers keep every report's stack readable.
ctest-sanitize:
	cmake -S core -B $(BUILD)/core-sanitize -DRB_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-g -O1" >/dev/null
	cmake --build $(BUILD)/core-sanitize -j$(JOBS)
	ctest --test-dir $(BUILD)/core-sanitize --output-on-failure -j$(JOBS)

# One pytest worker per core (pytest-xdist); a file's tests stay on one worker, so its module
# fixtures (a detailed run, a compiled FMU) are made once.
PYTEST_PARALLEL := -n $(JOBS) --dist loadfile --no-loadscope-reorder

# System packages two tests need (Debian names), installed by an explicit, announced step of `make test`:
# wine64 runs the FMU's win64 binary (tests/unit/fmu/test_fmu_platforms.py), chromium loads the HIL
# dashboard (tests/unit/hil/test_dashboard_browser.py). Only as root with apt-get, the dpkg output going
# to $(BUILD)/system-packages.log; SYSTEM_PACKAGES=0 skips the step; without them those tests skip and
# say why.
SYSTEM_PACKAGES ?= 1
APT_LOG = $(BUILD)/system-packages.log

system-packages:
	@if [ "$(SYSTEM_PACKAGES)" = 0 ]; then echo "system packages: skipped (SYSTEM_PACKAGES=0)"; exit 0; fi; \
	missing=""; \
	command -v wine64 >/dev/null 2>&1 || command -v wine >/dev/null 2>&1 || [ -x /usr/lib/wine/wine64 ] || missing="wine64"; \
	command -v chromium >/dev/null 2>&1 || missing="$$missing chromium"; \
	if [ -z "$$missing" ]; then echo "system packages: wine64 and chromium present"; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	  echo "system packages: installing$$missing with apt-get (log: $(APT_LOG); SYSTEM_PACKAGES=0 skips)"; \
	  mkdir -p $(BUILD) && apt-get update -q >$(APT_LOG) 2>&1 && \
	  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $$missing >>$(APT_LOG) 2>&1 || \
	    echo "system packages: apt-get failed (see $(APT_LOG)): the tests that need$$missing will skip"; \
	else echo "system packages:$$missing missing and not root: the tests that need them will skip"; fi

wine browser: system-packages

# One worker more than cores: the paced 8-car HIL stop (tests/unit/hil/test_loopback.py, 170 s on the
# wall clock, a few per cent of a core) would otherwise leave its worker's core idle that long.
# --no-loadscope-reorder: files handed out in tests/conftest.py's order (those with slow tests first),
# not xdist's by number of tests, which starts the long files last.
pytest: install system-packages
	$(PY) -m pytest -q -n $$(( $(JOBS) + 1 )) --dist loadfile --no-loadscope-reorder -m "not long" --durations=15

# The statistical must-holds that take tens of minutes of CPU (ETCS: the method against a brute
# force on the plant, five seeds giving the same coded Kdry): not part of `make test`.
test-long: install
	$(PY) -m pytest -q -n $(JOBS) --dist load -m long --durations=15

# The Python tests again, with the C core built under AddressSanitizer and UBSan.
# Python itself is not instrumented, so leak detection is left to the C tests. The FMU tests are
# left out: they run FMU binaries gcc builds from the exported sources, not this core library, and
# build their own ASan/UBSan FMUs for the fuzz and memory tests in the plain pass. The docs tests
# (Sphinx over the pages), the sequences (Python steps over the run API the simulation tests
# cover), the command line, the campaigns (processes and Dask workers over the same run API) and
# the ETCS analyses (statistics in Python over the batches of runs the simulation tests cover)
# add time here, not coverage of the core; so do the slow tests (processes killed mid-write,
# thousands of Python refusals: each says why it is slow).
pytest-sanitize: install ctest-sanitize
	LD_PRELOAD="$$(gcc -print-file-name=libasan.so) $$(gcc -print-file-name=libubsan.so)" \
	ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
	RAILBRAKE_CORE_LIBRARY=$(CURDIR)/$(BUILD)/core-sanitize/librailbrake_core_sanitize.so \
	$(PY) -m pytest -q $(PYTEST_PARALLEL) -m "not slow and not long" -p no:cacheprovider --durations=15 \
	    --ignore=tests/unit/fmu --ignore=tests/unit/docs --ignore=tests/unit/sequence \
	    --ignore=tests/unit/cli --ignore=tests/unit/campaign --ignore=tests/unit/etcs

# Every verification and validation case (docs/validation-cases.md): the HTML report into out/,
# the Markdown summary into docs/validation.md. Failing validation cases are findings, so only a
# failing verification case or a broken case folder fails the target (--strict).
validate: install
	$(VENV)/bin/railbrake validate --report $(OUT)/validation.html --markdown $(OUT)/validation.md --strict

# The fuzz suite, long runs (bounded smoke runs of each are part of `make test`): FMI call sequences
# (10^6 calls per FMI version), the HIL frame decoder (libFuzzer with clang, else a gcc mutational
# loop), the configuration mutator and the Python API argument fuzzer. Each target's figures, with
# the date and the command, go to $(FUZZ_RESULTS) (tools/fuzz_record.py), which docs/robustness.md
# reads when the docs are built; a failing run records nothing.
FUZZ_FMI_CALLS ?= 1000000
FUZZ_FRAMES ?= 20000000
FUZZ_CONFIG_VARIANTS ?= 20000
FUZZ_API_CALLS ?= 50000
FUZZ_SANITIZE := -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
FUZZ_RESULTS ?= docs/results/fuzz.json
FUZZ_RECORD = $(PYTHON) tools/fuzz_record.py $(FUZZ_RESULTS)

fuzz: fuzz-fmi fuzz-frames fuzz-python

fuzz-fmi: install
	RAILBRAKE_FUZZ_FMI_CALLS=$(FUZZ_FMI_CALLS) $(FUZZ_RECORD) "make fuzz-fmi FUZZ_FMI_CALLS=$(FUZZ_FMI_CALLS)" -- \
	  $(PY) -m pytest -q -s -p no:cacheprovider tests/unit/fmu/test_fmu_fuzz.py

fuzz-frames:
	mkdir -p $(BUILD)/fuzz
	if command -v clang >/dev/null 2>&1; then \
	  clang -std=c99 $(FUZZ_SANITIZE) -fsanitize=fuzzer -DRB_LIBFUZZER -Icore/include core/tests/fuzz_hil_frame.c \
	    core/src/hil_frame.c core/src/hil_mac.c core/src/common.c -o $(BUILD)/fuzz/hil_frame_fuzz -lm && \
	  $(FUZZ_RECORD) "make fuzz-frames FUZZ_FRAMES=$(FUZZ_FRAMES)" -- \
	    $(BUILD)/fuzz/hil_frame_fuzz -runs=$(FUZZ_FRAMES) -max_len=1024; \
	else \
	  echo "clang not found: the gcc mutational loop instead of libFuzzer"; \
	  gcc -std=c99 $(FUZZ_SANITIZE) -Icore/include core/tests/fuzz_hil_frame.c core/src/hil_frame.c core/src/hil_mac.c \
	    core/src/common.c -o $(BUILD)/fuzz/hil_frame_fuzz -lm && \
	  $(FUZZ_RECORD) "make fuzz-frames FUZZ_FRAMES=$(FUZZ_FRAMES)" -- $(BUILD)/fuzz/hil_frame_fuzz $(FUZZ_FRAMES); \
	fi

fuzz-python: install
	RAILBRAKE_FUZZ_CONFIG_VARIANTS=$(FUZZ_CONFIG_VARIANTS) RAILBRAKE_FUZZ_API_CALLS=$(FUZZ_API_CALLS) \
	$(FUZZ_RECORD) "make fuzz-python FUZZ_CONFIG_VARIANTS=$(FUZZ_CONFIG_VARIANTS) FUZZ_API_CALLS=$(FUZZ_API_CALLS)" -- \
	  $(PY) -m pytest -q -s -p no:cacheprovider tests/unit/fuzz

# The wheel and sdist into dist/: one py3-none wheel for every CPython >= 3.10 (the core is a plain C
# library loaded with ctypes), its core compiled by zig's clang against glibc 2.17 (the `fmu` extra's
# toolchain, which builds the FMU binaries too), then checked and tagged manylinux2014 (manylinux_2_17)
# by auditwheel, so pip takes it on RHEL 7/8-class systems; LICENSE is in both.
# tests/unit/wheel/test_wheel.py (make wheel-test) installs and runs it in a fresh venv per CPython found.
ARCH := $(shell uname -m)
ZIG_CC := $(abspath $(BUILD))/zig-cc-glibc2.17

wheel: install
	$(PY) -m pip install -q '.[dist,fmu]' build
	mkdir -p $(BUILD) && printf '#!/bin/sh\nexec "%s" -m ziglang cc -target $(ARCH)-linux-gnu.2.17 "$$@"\n' \
	    "$(abspath $(PY))" > $(ZIG_CC) && chmod +x $(ZIG_CC)
	rm -rf dist $(BUILD)/wheel-glibc2.17 && CC=$(ZIG_CC) $(PY) -m build --sdist --wheel \
	    -C build-dir=$(abspath $(BUILD))/wheel-glibc2.17 --outdir dist/raw .
	PATH=$(VENV)/bin:$$PATH $(VENV)/bin/auditwheel repair --plat manylinux2014_$(ARCH) --wheel-dir dist dist/raw/*.whl
	mv dist/raw/*.tar.gz dist/ && rm -rf dist/raw && ls dist

wheel-test: wheel
	RAILBRAKE_WHEEL=$$(ls dist/*.whl) $(PY) -m pytest -q -p no:cacheprovider tests/unit/wheel

bench: install
	$(PY) bench/run_all.py

clean:
	rm -rf $(BUILD) $(VENV) $(OUT)
