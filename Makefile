# The two commands of the README, plus a few helpers. All build through CMake presets.
JOBS ?= $(shell nproc)
BUILD := build/release
LANCER := $(BUILD)/lancer

.PHONY: render test build configure deps bench bench-render bench-micro bench-embree test-sanitize fuzz clean

deps:
	@scripts/install-deps.sh

configure: deps
	cmake --preset release >/dev/null

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# Only the program: a first `make render` need not compile the tests and benchmarks.
render: configure
	cmake --build $(BUILD) -j $(JOBS) --target lancer
	@mkdir -p out
	$(LANCER) render scenes/cornell-box.gltf -o out/cornell-box.exr -o out/cornell-box.png

test: build
	ctest --test-dir $(BUILD) -j $(JOBS) --output-on-failure

# Medians over repetitions: the machine is shared and noisy (see docs/performance.md).
BENCH_FLAGS ?= --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

bench-micro: build
	$(BUILD)/bench/lancer_bench_micro $(BENCH_FLAGS)

# Lancer beside Embree 3 on the same triangles and rays (built when Embree is installed).
bench-embree: build
	$(BUILD)/bench/lancer_bench_embree $(BENCH_FLAGS)

# The whole suite under AddressSanitizer + UndefinedBehaviorSanitizer, less the scale tests:
# those named *Heavy* (tens of millions of watertightness rays, a 600,000-triangle build, a
# timed 512x512 interrupt, SPPM against the path tracer over 12 renders) and KdPacketCamera
# (1.6 million camera rays per ISA). They repeat code paths the sanitized suite runs at small
# scale (KdPacket, KdRobustness, WatertightMesh, KdMemory, RenderProcess, Sppm) at a size the
# sanitizers make too slow for CI (KdPacketCamera alone: about 1,000 test-seconds). `make test` runs them; SANITIZE_EXCLUDE= runs everything.
SANITIZE_EXCLUDE ?= Heavy|KdPacketCamera
test-sanitize: deps
	cmake --preset sanitize >/dev/null
	cmake --build build/sanitize -j $(JOBS)
	ctest --test-dir build/sanitize -j $(JOBS) --output-on-failure $(if $(SANITIZE_EXCLUDE),-E '$(SANITIZE_EXCLUDE)')

# libFuzzer on every reader, under ASan + UBSan, with clang (tests/fuzz/README.md).
# Fails when any target finds a crash; the input is kept in build/fuzz/fuzz-findings.
FUZZ_SECONDS ?= 300
FUZZ_TARGETS := gltf obj ray_file
fuzz: deps
	cmake --preset fuzz >/dev/null
	cmake --build build/fuzz -j $(JOBS) --target $(FUZZ_TARGETS:%=%_fuzz)
	tests/fuzz/run_fuzzers.sh build/fuzz $(FUZZ_SECONDS) $(FUZZ_TARGETS)

clean:
	rm -rf build out

# lancer bench: the scene suite, packet vs single vs Embree (BENCH_ARGS, e.g. --quick).
bench: configure
	cmake --build $(BUILD) -j $(JOBS) --target lancer lancer-bench
	$(LANCER) bench $(BENCH_ARGS)

# Whole renders: paths/s, Mrays/s and the traversal share per scene, and beside Blender's
# Cycles at equal error when `blender` is installed (optional: apt-get install blender
# python3-numpy). BENCH_RENDER_ARGS, e.g. --scenes cornell-box --spp 64; --help lists them.
bench-render: configure
	cmake --build $(BUILD) -j $(JOBS) --target lancer lancer-bench
	$(LANCER) bench --render $(BENCH_RENDER_ARGS)

# The README gallery (docs/images/), rendered by the path tracer at a fixed sample count, so
# the images are the same on any machine and thread count. About 2 CPU-minutes per image.
.PHONY: gallery
GALLERY_SPP ?= 128
GALLERY_RENDER = $(LANCER) render --spp $(GALLERY_SPP) --filter gaussian --no-progress
gallery: configure
	cmake --build $(BUILD) -j $(JOBS) --target lancer
	$(GALLERY_RENDER) scenes/cornell-box.gltf -o docs/images/cornell-box.png
	$(GALLERY_RENDER) scenes/cornell-box-spheres.gltf -o docs/images/cornell-box-spheres.png
	$(GALLERY_RENDER) scenes/textured/still-life.gltf -o docs/images/still-life.png
	$(GALLERY_RENDER) scenes/cornell-box-dof.gltf -o docs/images/cornell-box-dof.png
	$(GALLERY_RENDER) scenes/cornell-box-motion.gltf --shutter 0.3,0.7 -o docs/images/cornell-box-motion.png
	$(LANCER) render scenes/cornell-box-spheres.gltf --integrator sppm --spp 256 --filter gaussian --no-progress \
		-o docs/images/cornell-box-spheres-sppm.png
