# Version header, live viewer, browser test, help and install; included by
# the Makefile (kept apart so the build rules above stay short).

# ---- version: git describe at build time ------------------------------------
# Rewritten only when the description changes, so a commit does not rebuild
# everything. TANDEM_VERSION=... overrides it (e.g. for a tarball without git).
VERSION_H := $(GEN)/c/tandem_version.h
$(VERSION_H): FORCE
	@mkdir -p $(@D)
	@v='$(TANDEM_VERSION)'; [ -n "$$v" ] || v=$$(git describe --tags --always --dirty 2>/dev/null || echo unknown); \
	 printf '#define TANDEM_VERSION "%s"\n' "$$v" > $@.tmp; \
	 if cmp -s $@.tmp $@; then rm -f $@.tmp; else mv $@.tmp $@; fi
$(OBJ)/src/daemons/common/version.o: $(VERSION_H)
FORCE:

# ---- viewer: Python bridge to Rerun's web viewer ------------------------------
VENV      := build/venv
VENV_PY   := $(VENV)/bin/python
PY_STAMP  := $(GEN)/python/.stamp
VIEW_ARGS ?=
$(PY_STAMP): $(LCM_FILES)
	@mkdir -p $(@D)
	@lcm-gen -p --ppath $(GEN)/python $(LCM_FILES)
	@touch $@
$(VENV)/.stamp: tools/viewer/requirements.txt
	@tools/deps.sh view
	@echo "  VENV  $(VENV) (rerun-sdk, lcm)"
	@$(firstword $(wildcard /usr/bin/python3) python3) -m venv $(VENV)
	@$(VENV)/bin/pip install -q --disable-pip-version-check -r $<
	@touch $@
viewer: $(VENV)/.stamp $(PY_STAMP) $(BIN)/tandem-scene
view: viewer
	@$(VENV_PY) tools/viewer/tandem_view.py $(VIEW_ARGS)
view-test: deps viewer
	@$(MAKE) --no-print-directory all
	@tools/deps.sh view-test
	@tools/view-test.sh $(if $(UPDATE_DOCS),--docs)

# ---- help ---------------------------------------------------------------------
help:
	@echo 'tandem make targets:'
	@echo '  make               build everything into build/ (V=1 shows the commands)'
	@echo '  make run           run the whole system (DURATION=S to stop after S s,'
	@echo '                     VIEW=1 with the browser viewer, RUN_ARGS="..." for tools/tandem-run)'
	@echo '  make test          make lint, unit + integration tests, then again under ASan/UBSan'
	@echo '  make lint          core layering (src/core/layers.mk), no POSIX/stdio in the core, no outside references,'
	@echo '                    error codes distinct and named, docs and figures current, no hidden state in src/'
	@echo '  make analyze       cppcheck over every C file (tools/cppcheck-suppressions.xml): zero findings'
	@echo '  make format-check  clang-format on every C file .clang-format-files names (make format rewrites them)'
	@echo '  make tidy          clang-tidy (.clang-tidy) over every C file: zero findings'
	@echo '  make unit | integration   one of the two test sets'
	@echo '  make view          browser viewer attached to a running bus (VIEW_ARGS="--help")'
	@echo '  make view-test     headless-Chromium test of the viewer (UPDATE_DOCS=1 writes docs/viewer.png)'
	@echo '  make spy           lcm-spy with every tandem type decoded'
	@echo '  make bench         benchmarks (figures printed, nothing asserted)'
	@echo '  make coverage      line and branch coverage of the unit and integration tests (gcovr)'
	@echo '  make cross         the core for m68k (68040) and arm-none-eabi (Cortex-M4F)'
	@echo '  make test-cross    the unit tests built for the 68040, run under qemu-m68k'
	@echo '  make budget        memory, stack and cycle budgets of the cross builds'
	@echo '  make fuzz          libFuzzer targets (clang), FUZZ_SECONDS=N each'
	@echo '  make multihost-test  the cell on three network namespaces vs one host (root)'
	@echo '  make fleet-hosts     a fleet on rover hosts in network namespaces vs one process (root)'
	@echo '  make install       PREFIX=/usr/local: binaries, types jar, man pages, pkg-config file'
	@echo '  make jar           build/lib/tandem_types.jar only'
	@echo '  make tools-venv    build/venv-tools: Python packages of tandem-log2mcap and its tests'
	@echo '  make mcap-test     tandem-log2mcap on a recorded 20 s run, checked message by message'
	@echo '  make urdf-test     tandem-scene --urdf read by yourdfpy, its FK against tandem-kin'
	@echo '  make deb           build/deb/tandem_VERSION_ARCH.deb with dpkg-deb'
	@echo '  make clean         remove build/'
	@echo 'variables: SAN=1 (sanitizer build in build/san), COV=1 (build/cov), V=1, PREFIX, DESTDIR, TANDEM_VERSION, DEB_MAINTAINER'

# ---- install ------------------------------------------------------------------
PREFIX  ?= /usr/local
DESTDIR ?=
MAN_DIR := build/man
install: all
	@tools/deps.sh install
	@tools/install.sh "$(DESTDIR)$(PREFIX)" "$(PREFIX)" $(BIN) $(CORE_LIB) $(TYPES_JAR) $(MAN_DIR)

.PHONY: viewer view view-test help install FORCE

# ---- tandem-log2csv: CSV printers generated for every message type ----------
$(GEN)/c/tandem_csv.c: $(LCM_FILES) tools/lcm2csv_gen.py $(GEN_STAMP)
	@python3 tools/lcm2csv_gen.py $(GEN)/c $(LCM_FILES)
$(LIB)/libtandem_lcm.a: $(GEN)/c/tandem_csv.c
$(OBJ)/tools/tandem_log2csv.o: $(GEN)/c/tandem_csv.c

# ---- tandem-log2mcap: MCAP with a JSON schema per type, Foxglove geometry ----
# The script runs from build/bin like every program; its decoders are
# lcm-gen -p's (PY_STAMP), its schemas generated from the same lcmtypes.
TOOLS_VENV := build/venv-tools
SCHEMAS    := $(GEN)/python/tandem_schemas.json
$(SCHEMAS): $(LCM_FILES) tools/mcap/lcm2schema_gen.py tools/lcm2csv_gen.py
	@mkdir -p $(@D)
	@python3 tools/mcap/lcm2schema_gen.py $(@D) $(LCM_FILES)
$(BIN)/tandem-log2mcap: tools/tandem-log2mcap $(PY_STAMP) $(SCHEMAS)
	@mkdir -p $(@D)
	@install -m 755 $< $@
all: $(BIN)/tandem-log2mcap
$(TOOLS_VENV)/.stamp: tools/mcap/requirements.txt
	@tools/deps.sh view
	@echo "  VENV  $(TOOLS_VENV) (mcap, yourdfpy)"
	@$(firstword $(wildcard /usr/bin/python3) python3) -m venv $(TOOLS_VENV)
	@$(TOOLS_VENV)/bin/pip install -q --disable-pip-version-check -r $<
	@touch $@
tools-venv: $(TOOLS_VENV)/.stamp
mcap-test: deps tools-venv
	@$(MAKE) --no-print-directory all
	@tools/mcap-test.sh
# the URDF of tandem-scene --urdf read by yourdfpy, its FK against tandem-kin
urdf-test: tools-venv $(BIN)/tandem-scene $(BIN)/tandem-kin
	@$(TOOLS_VENV)/bin/python tools/urdf_check.py $(BIN)
.PHONY: tools-venv mcap-test urdf-test

# ---- make deb: a Debian package with dpkg-deb ---------------------------------
deb: all
	@tools/deps.sh install
	@tools/deb.sh build/deb $(BIN) $(CORE_LIB) $(TYPES_JAR) build/deb/man
.PHONY: deb
