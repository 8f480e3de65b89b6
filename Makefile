# Thin wrapper over CMake. `make run` and `make test` install missing Debian packages first.
BUILD ?= build
JOBS  ?= 2
SCENE ?= options/gregoire_d50_hn.opts
# Open MPI refuses root without these; CI runs as root.
export OMPI_ALLOW_RUN_AS_ROOT := 1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM := 1

.PHONY: all deps build run test sanitize format clean

all: build

deps:
	@bash scripts/install-deps.sh

# the generated Makefile, not CMakeCache.txt: a configure that failed (a package missing) leaves the cache
# behind, and the next make must configure again
$(BUILD)/Makefile:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/Makefile
	cmake --build $(BUILD) -j $(JOBS)

run: build
	$(BUILD)/pdimplicit -options_file $(SCENE) -pd_progress

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# the fast tests (CTest label "fast") on a build with AddressSanitizer and UndefinedBehaviorSanitizer; leak
# reports are off: Open MPI and PETSc keep allocations until the process exits
sanitize: deps
	cmake -S . -B $(BUILD)-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPD_SANITIZE=ON
	cmake --build $(BUILD)-sanitize -j $(JOBS)
	cd $(BUILD)-sanitize && ASAN_OPTIONS=detect_leaks=0:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1 \
	  ctest --output-on-failure -j $(JOBS) -L fast

format:
	clang-format -i src/*.c src/*/*.c src/*/*.h include/*.h tests/*.c

clean:
	rm -rf $(BUILD)
