# paraflex — set up and run. `make demo` and `make test` install what is missing (Debian
# packages, the Python venv for tools/ and meshes/) and are quick when everything is there.

SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
CARGO ?= cargo
BIN := $(or $(CARGO_TARGET_DIR),target)/release/paraflex
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian packages: HDF5 for the hdf5 crate; the shared libraries the PyPI gmsh wheel loads.
DEB_PACKAGES := libhdf5-dev pkg-config libglu1-mesa libgl1 libxrender1 libxcursor1 libxfixes3 \
	libxext6 libxft2 libfontconfig1 libxinerama1 libx11-6 libgomp1

.PHONY: demo test deps sysdeps venv build bench-read bench-transient clean

demo: deps
	$(CARGO) build --release --quiet
	$(BIN) check decks/robot/l2r_free.dat
	@mkdir -p out
	$(BIN) run decks/robot/l2r_free.dat -o out/demo.h5

test: deps
	$(CARGO) test --quiet

deps: sysdeps venv

sysdeps:
	@missing=$$(for p in $(DEB_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
		echo "installing Debian packages:" $$missing; \
		$(SUDO) apt-get update -q && $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $$missing; \
	fi

venv: $(VENV)/.installed

$(VENV)/.installed: tools/requirements.txt
	@[ -x $(PY) ] || python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r tools/requirements.txt
	@touch $@

# Mesh includes of the case-study scenes (meshes/README.md): the committed "test" variants,
# and the large "full" variants in meshes/full/ (not committed).
.PHONY: meshes meshes-full
meshes: deps
	$(PY) meshes/build.py

meshes-full: deps
	$(PY) meshes/build.py --full

# Reading speed against pyNastran on a generated 1-million-grid deck (not part of the tests).
bench-read: deps
	$(CARGO) build --release --quiet
	bash tools/bench/read_speed.sh

# Transient integrators on the blade pROM: Δt vs error vs time (not part of the tests).
bench-transient: deps
	$(CARGO) build --release --quiet
	$(PY) tools/bench/transient_bench.py --paraflex $${CARGO_TARGET_DIR:-target}/release/paraflex

clean:
	$(CARGO) clean
	rm -rf $(VENV)
