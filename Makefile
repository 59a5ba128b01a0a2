# tetcontact: the user's entry point.
#
#   make run     install missing Debian packages (as root), configure, build the program (not the
#                tests), run the default case
#   make test    the same, building the tests too, then the whole test suite (ctest)
#   make build   configure and build the program and the tests; the program is build/tetcontact
#   make program configure and build the program alone
#   make bench   build and run the benchmark programs (not tests: they print figures)
#   make format  reformat the sources with clang-format
#
# Variables: BUILD_DIR (build), BUILD_TYPE (Release), JOBS (all cores), CASE, OUT.

BUILD_DIR  ?= build
BUILD_TYPE ?= Release
JOBS       ?= $(shell nproc 2>/dev/null || echo 2)
CASE       ?= data/cases/cubes-edge.yaml
OUT        ?= results/$(basename $(notdir $(CASE)))

# Debian packages the build, the tests and the tools need.
DEB_PACKAGES := cmake make g++ pkg-config libeigen3-dev libyaml-cpp-dev libfcl-dev libccd-dev \
                libcgal-dev libgmp-dev libmpfr-dev zlib1g-dev libtbb-dev nlohmann-json3-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev \
                libmetis-dev libopenmpi-dev openmpi-bin \
                clang-format python3 python3-numpy python3-vtk9 python3-matplotlib python3-pytest procps

.PHONY: all deps configure build program run test bench format clean

all: build

# Install what is missing when root; otherwise say exactly what to install.
deps:
	@missing=""; \
	for p in $(DEB_PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = "0" ]; then \
	    echo "make: installing missing Debian packages:$$missing"; \
	    DEBIAN_FRONTEND=noninteractive apt-get update -qq && \
	    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null || exit 1; \
	  else \
	    echo "make: missing Debian packages:$$missing"; \
	    echo "make: install them with: sudo apt-get install$$missing"; \
	    exit 1; \
	  fi; \
	fi

configure: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE)

build: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

program: deps configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target tetcontact

run: program
	$(BUILD_DIR)/tetcontact run $(CASE) --out $(OUT) --force

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DTETCONTACT_BENCHMARKS=ON
	cmake --build $(BUILD_DIR) -j $(JOBS) --target tetcontact_bench
	$(BUILD_DIR)/tetcontact_bench

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD_DIR)
