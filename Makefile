# Two commands for a new user (README "Quick start"):
#   make run    install what is missing, build, open the workbench on the default preset
#   make test   install what is missing, build, run every test
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release
# A compiler cache speeds rebuilds where one is installed (optional; CI builds without it).
CCACHE := $(shell command -v ccache 2>/dev/null)
ifneq ($(CCACHE),)
CMAKE_FLAGS += -DCMAKE_CXX_COMPILER_LAUNCHER=$(CCACHE)
endif

.PHONY: setup configure build run test bench screenshots clean format format-check fuzz sanitize

setup:
	bash scripts/setup.sh

configure: setup
	cmake -S . -B $(BUILD) $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

run: build
	$(BUILD)/app/kfw $(ARGS)

test: build
	cd $(BUILD) && ctest -j $(JOBS) --output-on-failure

bench: build
	cmake --build $(BUILD) -j $(JOBS) --target kfw_bench
	$(BUILD)/bench/kfw_bench

screenshots: build
	bash scripts/screenshots.sh $(BUILD)

# Hardening (docs/hardening.md "Fuzzing", "Sanitizers"), local and long; CI's `make test` needs neither.
# make fuzz FUZZ_SECONDS=N   every libFuzzer harness for N seconds, FUZZ_JOBS at a time (clang;
#                            build-fuzz/)
# make sanitize              the whole suite under AddressSanitizer + UBSan (build-asan/)
# -O1 -g1: fast to build, fast to run.
FUZZ_SECONDS ?= 60
FUZZ_JOBS ?= 1
FUZZ_FLAGS := -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
fuzz: setup
	bash scripts/setup-fuzz.sh
	cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g1" \
	  -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_CXX_FLAGS="$(FUZZ_FLAGS)" -DKFW_FUZZ=ON \
	  -DKFW_BUILD_GUI=OFF -DKFW_BUILD_TESTS=OFF \
	  -DKFW_BUILD_BENCH=OFF $(filter -DCMAKE_CXX_COMPILER_LAUNCHER=%,$(CMAKE_FLAGS))
	cmake --build build-fuzz -j $(JOBS) --target kfw_fuzz
	bash tests/fuzz/run.sh build-fuzz $(FUZZ_SECONDS) $(FUZZ_JOBS)

# SANITIZE_GUI=OFF leaves the GUI and its tests out (the engine and CLI tests only).
# SANITIZE_SKIP_SLOW=1 leaves out the tests matching SAN_SLOW, the two over a minute under ASan:
# the tuning over the real 68 000-row IMU log (31 s in Release, 505 s under ASan) and radome's
# renewal acceptance over 10 seeds of a 49-mode IMM (2.3 s, 317 s); and the real single-node Slurm
# array (10 s of scheduling, no code of ours to check twice). `make test` runs them in Release.
# .ci/run: `make test`, then `make sanitize SANITIZE_GUI=OFF SANITIZE_SKIP_SLOW=1`.
# The test binaries run in JOBS gtest shards each (tests/run_sharded.sh), not one process per test
# as ctest does: an ASan process starts in 0.1 s and checks for leaks at exit in 0.4 s (GCC's
# builds took 2-3 s to start).
# clang, as for make fuzz: with -fsanitize=address,undefined it compiles kfw's Eigen-heavy files in
# about half GCC 12's time (model_kf.cpp 59 s against 111 s), and the build is the long part.
# -O1 -g1 (line tables: enough for a report's file:line).
SAN_CXX ?= clang++
SANITIZE_GUI ?= ON
SANITIZE_SKIP_SLOW ?=
SAN_SLOW := Tuning.RealLog*:ImmModelRadome.TheBuiltInsRenewalTestHoldsForTheFile:ScaleSlurm.RealSlurm*
SAN_BINS := kfw_engine_tests kfw_cli_tests $(if $(filter ON,$(SANITIZE_GUI)),kfw_gui_tests)
SAN_ENV := ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp:print_suppressions=0 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ASAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer
sanitize: setup
	bash scripts/setup-fuzz.sh
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=$(SAN_CXX) \
	  -DCMAKE_CXX_FLAGS="$(ASAN_FLAGS)" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
	  -DKFW_BUILD_GUI=$(SANITIZE_GUI) -DKFW_BUILD_BENCH=OFF \
	  $(filter -DCMAKE_CXX_COMPILER_LAUNCHER=%,$(CMAKE_FLAGS))
	# The build runs the test binaries too (gtest test discovery): the same suppressions apply.
	$(SAN_ENV) cmake --build build-asan -j $(JOBS)
	$(SAN_ENV) bash tests/run_sharded.sh build-asan $(JOBS) '$(if $(SANITIZE_SKIP_SLOW),$(SAN_SLOW))' \
	  $(SAN_BINS)

# The committed .clang-format with clang-format 14 (scripts/setup.sh installs it); CI runs
# format-check (.ci/run) and fails on any unformatted tracked source.
CLANG_FORMAT ?= clang-format-14
format: setup
	git ls-files -z '*.h' '*.cpp' | xargs -0 $(CLANG_FORMAT) -i
format-check: setup
	git ls-files -z '*.h' '*.cpp' | xargs -0 $(CLANG_FORMAT) --dry-run -Werror

clean:
	rm -rf $(BUILD) build-fuzz build-asan
