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

.PHONY: demo test deps sysdeps venv build bench-read bench-prom validate-prom bench-transient bench-estimate bench-amanda bench-fmb bench-optimize \
	reference-calculix reference-exudyn reference-pymoo exudyn-plot fourbar-plots mutants clean

demo: deps
	$(CARGO) build --release --quiet
	$(BIN) check decks/robot/l2r_free.dat
	@mkdir -p out
	$(BIN) run decks/robot/l2r_free.dat -o out/demo.h5

test: deps
	$(CARGO) fmt --check
	$(CARGO) clippy --quiet --all-targets -- -D warnings
	$(CARGO) test --quiet
	$(PY) -m pytest -q tools

deps: sysdeps venv

sysdeps:
	@missing=$$(for p in $(DEB_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
		echo "installing Debian packages:" $$missing; \
		$(SUDO) apt-get update -q && $(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -q $$missing; \
	fi

venv: $(VENV)/.installed

$(VENV)/.installed: tools/requirements.txt tools/pyproject.toml
	@[ -x $(PY) ] || python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r tools/requirements.txt
	$(PY) -m pip install --quiet --disable-pip-version-check --no-deps -e tools
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

# pROM speed against error (tools/bench/prom_speed.py; docs/performance.md), and the
# full-size pROM validation plots (error maps, angle sweep) — not part of the tests.
bench-prom: deps
	$(CARGO) build --release --quiet
	$(CARGO) build --release --quiet --example prom_eval --example prom_frf
	$(PY) tools/bench/prom_speed.py

validate-prom: deps
	$(CARGO) build --release --quiet
	$(PY) tools/prom/error_map.py decks/blade/blade_prom_e_rho.dat --pair 71:3 --grid 11 -o docs/img/blade_prom_error_map.png
	$(PY) tools/prom/error_map.py decks/prom/blade_prom_e_rho_10.dat --pair 71:3 --grid 11 -o docs/img/blade_prom_error_map_10.png
	$(PY) tools/prom/angle_sweep.py decks/prom/l2r_composite_prom_theta_90.dat decks/prom/l2r_composite_prom_theta_45.dat \
		--pair 1000002:3 --step 2.5 -o docs/img/l2r_composite_prom_angle_sweep.png

# Transient integrators on the blade pROM: Δt vs error vs time (not part of the tests).
bench-transient: deps
	$(CARGO) build --release --quiet
	$(PY) tools/bench/transient_bench.py --scene blade --paraflex $${CARGO_TARGET_DIR:-target}/release/paraflex
	$(PY) tools/bench/transient_bench.py --scene link --paraflex $${CARGO_TARGET_DIR:-target}/release/paraflex

# The flexible four-bar (SOL FMB, thesis §4.4): CPU time, Newton iterations per step and the
# eq. 4.11 error against a finer step for BDF1 at 1 ms, then each GGL integrator at 2, 1 and
# 0.5 ms (tools/bench/fourbar_bench.py; docs/fourbar.md "Speed") — prints, not part of the tests.
bench-fmb: deps
	$(CARGO) build --release --quiet
	$(PY) tools/bench/fourbar_bench.py --integrators --repeat 5 --paraflex $(BIN)

# MOOPT GRAD against NSGA-II on the four-bar design study at equal budgets (hypervolume
# against evaluations), and the forward sensitivities against central differences over 300
# steps (tools/bench/optimize_bench.py; docs/optimize.md "Gradient-based search") — prints,
# not part of the tests.
bench-optimize: deps
	$(CARGO) build --release --quiet
	$(PY) tools/bench/optimize_bench.py --paraflex $(BIN)

# The AMANDA-EKF four-bar cases over the whole measured second (tests/amanda_fourbar.rs, the
# ignored tests): ms per step against the error of E_C (and of the input) over the last 20 %,
# with Table 9.1's bound on the E_C-and-input case, and its three-moduli and degrading-E_C rows
# with sensor sets 1 and 2 printed (docs/estimation.md "Mechanisms").
bench-amanda: deps
	$(CARGO) test --release --quiet --test amanda_fourbar -- --ignored --nocapture

# SOL ESTIMATE filter speed against the goal of 10x real time: steps/s in physical and modal
# coordinates on the blade pROM and on its clamped one-material variant, and the error for a few
# covariance settings (examples/estimate_bench.rs; docs/estimation.md "Filter speed") — prints,
# not part of the tests.
bench-estimate: deps
	$(CARGO) build --release --quiet
	$(CARGO) build --release --quiet --example estimate_bench
	tmp=$$(mktemp -d) && for d in blade_prom_sensors blade_prom_clamped blade_prom_sensors_small; do \
		$(BIN) run decks/estimate/$$d.dat -o $$tmp/$$d.h5 > /dev/null || exit 1; \
	done && bench=$(or $(CARGO_TARGET_DIR),target)/release/examples/estimate_bench && \
	$$bench $$tmp/blade_prom_sensors.h5 && $$bench $$tmp/blade_prom_clamped.h5 && \
	$$bench $$tmp/blade_prom_sensors_small.h5 3 $$tmp/blade_prom_sensors.h5; rc=$$?; rm -rf $$tmp; exit $$rc

# Mutation testing of the numerical kernels (docs/mutation-testing.md): cargo-mutants plants
# small bugs in each file of MUTANTS_FILES and checks that the file's tests
# (tools/mutants/modules.tsv) catch them; tools/mutants/report.py writes the caught ratios and
# the account of every survivor into the docs. Slow (one incremental build per mutant, run under
# `nice` on one job), so not part of `make test`: run it on the kernels a change touches, e.g.
# `make mutants MUTANTS_FILES=src/linalg/cholesky.rs`.
MUTANTS_VERSION := 27.1.0
MUTANTS_KERNELS := src/dynamics/integrators.rs src/linalg/cholesky.rs src/linalg/eigen.rs \
	src/estimate/filter.rs src/estimate/ekf.rs src/fe/solid.rs src/fe/shell.rs \
	src/assembly/constraints.rs src/dynamics/prescribed.rs src/multibody/inertia.rs \
	src/multibody/integrator.rs
MUTANTS_FILES ?= $(MUTANTS_KERNELS)
mutants: sysdeps
	@$(CARGO) mutants --version 2>/dev/null | grep -qx 'cargo-mutants $(MUTANTS_VERSION)' || \
		$(CARGO) install --locked cargo-mutants --version $(MUTANTS_VERSION)
	bash tools/mutants/run.sh $(MUTANTS_FILES)
	python3 tools/mutants/report.py $(MUTANTS_KERNELS)

# The CalculiX references (tools/calculix/README.md): the Debian package calculix-ccx installed
# here only (not a dependency of paraflex or its tests), then every generator run; the outputs in
# decks/verify/ and reference/calculix/ are committed (~5 min).
reference-calculix: deps
	@dpkg -s calculix-ccx >/dev/null 2>&1 || { $(SUDO) apt-get update -q && \
		$(SUDO) env DEBIAN_FRONTEND=noninteractive apt-get install -y -q calculix-ccx; }
	$(PY) tools/calculix/make_references.py
	$(PY) tools/calculix/make_references.py --hard
	$(PY) tools/calculix/solid_same_mesh.py

# The independent multibody peer: Exudyn (installed into the venv here only; not a dependency
# of paraflex or its tests) runs the rigid four-bar (reference/exudyn/fourbar_rigid.json) and
# the flexible one on link artifacts paraflex builds with every grid's basis rows
# (reference/exudyn/fourbar_flexible.json, ~3 min).
reference-exudyn: deps
	$(PY) -m pip install --quiet --disable-pip-version-check -r tools/exudyn/requirements.txt
	$(CARGO) build --release --quiet
	$(PY) tools/exudyn/fourbar.py
	$(PY) tools/exudyn/fourbar_flexible.py --paraflex $(BIN)

# pymoo, the NSGA-II and hypervolume peer of src/optimize (tools/optimize/pymoo_reference.py):
# reference/optimize/{hypervolume,nsga2_zdt,nsga2_mixed}.json, committed (~3 min).
reference-pymoo: deps
	$(PY) -m pip install --quiet --disable-pip-version-check -r tools/optimize/requirements.txt
	$(PY) tools/optimize/pymoo_reference.py

# paraflex against Exudyn on the flexible four-bar: docs/img/fourbar_exudyn.png
# (tools/plot/fourbar_exudyn.py, reads reference/exudyn/fourbar_flexible.json).
exudyn-plot: deps
	$(CARGO) build --release --quiet
	$(PY) tools/plot/fourbar_exudyn.py --paraflex $(BIN)

# The four-bar's README pictures (docs/img/fourbar_mechanism.png, fourbar_pfmb_vs_fmb.png):
# pFMB against FMB histories like thesis Fig. 4.6-4.11 (tools/plot/fourbar_histories.py, ~1 min).
fourbar-plots: deps
	$(CARGO) build --release --quiet
	$(PY) tools/plot/fourbar_histories.py --paraflex $(BIN)

# ParaView reads the XDMF files: renders the first mode shape of the demo bracket plate (warped,
# coloured by the displacement magnitude) to docs/img/paraview_bracket_mode1.png under Xvfb and
# checks the picture is not blank (tools/xdmf/paraview_render.py) — not part of the tests.
.PHONY: paraview-check
paraview-check: deps
	@$(MAKE) --no-print-directory sysdeps DEB_PACKAGES="paraview python3-paraview xvfb xauth"
	$(CARGO) build --release --quiet
	@mkdir -p out/paraview
	$(BIN) run decks/demo/bracket_plate.dat -o out/paraview/bracket.h5 > /dev/null
	xvfb-run -a pvpython tools/xdmf/paraview_render.py out/paraview/bracket_1_modes.xdmf \
		-o docs/img/paraview_bracket_mode1.png

clean:
	$(CARGO) clean
	rm -rf $(VENV)
