# Thin wrapper over CMake. `make build` and `make test` are the README's set-up commands
# (`make demo` runs the default scene): each installs missing Debian packages first (as root).
JOBS ?= 2
CMAKE_FLAGS ?=

.PHONY: deps build demo test clean

deps:
	sh cmake/install-deps.sh

build: deps
	cmake -S . -B build -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)
	cmake --build build -j $(JOBS)

# The program's last line says where the frames and log.csv went; then how to watch it.
demo: build
	./build/softbond run scenes/default.yaml --output out/demo
	@echo "next: ./build/softbond view scenes/default.yaml   (the same scene in the viewer; h lists its keys)"

# Four configurations: float (the default), double, float under the
# address and undefined-behaviour sanitizers, and the threads' tests (label
# thread: the solver's team, the state and pose buffers, the contact pass, the
# xpbd sweeps' waits between blocks) under the thread sanitizer.
# The fuzz corpus's replay (label fuzz, tests/fuzz/) runs under the address
# and undefined-behaviour sanitizers only, where a memory error shows.
# The viewer's tests (label viewer, also no_sanitizer: tests/test_viewer.c
# under xvfb-run with Mesa's llvmpipe, tests/test_film.c with povray and
# ffmpeg) run in float and double only: Mesa is not built for the sanitizers.
test: deps
	cmake -S . -B build -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)
	cmake --build build -j $(JOBS)
	cd build && ctest --output-on-failure -j $(JOBS) -LE fuzz
	cmake -S . -B build-double -DCMAKE_BUILD_TYPE=Release -DSB_DOUBLE=ON $(CMAKE_FLAGS)
	cmake --build build-double -j $(JOBS)
	cd build-double && ctest --output-on-failure -j $(JOBS) -LE fuzz
	cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSB_SANITIZE=ON $(CMAKE_FLAGS)
	cmake --build build-asan -j $(JOBS)
	cd build-asan && ASAN_OPTIONS=detect_leaks=1 ctest --output-on-failure -j $(JOBS) -LE no_sanitizer
	cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSB_SANITIZE_THREAD=ON $(CMAKE_FLAGS)
	cmake --build build-tsan -j $(JOBS) --target test_runtime test_contact test_self_contact test_haptics_buffer test_pbd
	cd build-tsan && TSAN_OPTIONS=halt_on_error=1 ctest --output-on-failure -L thread

clean:
	rm -rf build build-double build-asan build-tsan out
