# tandem: one Makefile. Build output goes only under build/ (bin/, lib/, gen/).
#   make            build everything (core library, messages, daemons, sim, tools)
#   make run        install missing Debian packages, then run the whole system
#   make test       install missing packages, make lint, then unit + integration tests,
#                   also rebuilt and rerun with -fsanitize=address,undefined
#   make bench      benchmarks (figures printed, nothing asserted)
#   make coverage   line and branch coverage of the unit and integration tests (gcovr)
#   make spy        lcm-spy with every tandem channel decoded
#   make cross      the core for m68k-linux-gnu (-m68040) and arm-none-eabi (Cortex-M4F)
#   make test-cross the unit tests built for the 68040, run under qemu-m68k
#   make budget     memory, stack and cycle budgets of the cross builds
#   make view       live 3D viewer in the browser (also: make run VIEW=1)
#   make multihost-test  the cell on three network namespaces (root)
#   make fleet-hosts     a fleet on rover hosts in network namespaces (root)
#   make help       every target and variable
#   make clean
# SAN=1 builds into build/san with the sanitizers on, COV=1 into build/cov
# with gcov instrumentation (make coverage).

# src/core/layers.mk (included below) defines the first rule; plain make is all
.DEFAULT_GOAL := all

CC       ?= cc
# quiet by default; V=1 shows every command
Q        := $(if $(V),,@)
PKGS     := lcm ode ccd libsodium yaml-0.1 libxml-2.0
WARN     := -std=c99 -Wall -Wextra -Wpedantic -Werror
OPT      ?= -O2 -g
ifeq ($(SAN),1)
BUILD    := build/san
OPT      := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
LDSAN    := -fsanitize=address,undefined
else ifeq ($(COV),1)
BUILD    := build/cov
OPT      := -O0 -g --coverage
LDSAN    := --coverage
else
BUILD    := build
# the core is the code of every control cycle, so it is built for speed:
# -O3 keeps IEEE semantics (no -ffast-math, no FP contraction on x86-64
# without -march), so its results are the bits -O2 gives; CORE_OPT= builds
# it like the rest
CORE_OPT ?= -O3
endif
BIN      := $(BUILD)/bin
LIB      := $(BUILD)/lib
OBJ      := $(BUILD)/obj
GEN      := build/gen
PKG_CFLAGS := $(shell pkg-config --cflags $(PKGS) 2>/dev/null)
PKG_LIBS   := $(shell pkg-config --libs $(PKGS) 2>/dev/null)
CMOCKA_LIBS := $(shell pkg-config --libs cmocka 2>/dev/null)
LAYER    := build/layer
# everything above the core: every core header, the daemon shell, the
# simulator's headers, the generated message types, LCM, ODE, libsodium
APP_CPPFLAGS = $(CORE_INC) -Isrc/platform/posix -I$(GEN)/c -Isrc/daemons/common -Isim -Isim/models \
               -D_POSIX_C_SOURCE=200809L $(PKG_CFLAGS)
CFLAGS   := $(WARN) $(OPT)
LDLIBS   := -lm

# ---- layout ----------------------------------------------------------------
# Every folder with sources has a module.mk that lists them (LinuxCNC's
# Submakefile idea); this file holds the one compile recipe and the link
# rules. The core is split by domain (src/core/<d>, public headers in
# include/tandem/<d>) and each domain compiles with only the include paths
# of the domains below it (src/core/layers.mk): an include across the
# layering stops the build with a message that names the rule.
CORE_SRC   :=
# per-domain include flags for the host and the cross builds: the public
# headers of the domains it may use, its own private headers, the stubs
core_cppflags = $(foreach d,$(LAYER_$(1)),-Iinclude/tandem/$(d)) -Isrc/core/$(1) -I$(LAYER)/$(1) -I$(CORE_POISON)
# every public core header, for the programs, tests and tools above the core
CORE_INC    = $(foreach d,$(CORE_DOMAINS),-Iinclude/tandem/$(d))
LCM_FILES  := $(wildcard lcmtypes/*.lcm)
GEN_STAMP  := $(GEN)/.stamp
TYPES_JAR  := build/lib/tandem_types.jar
PROGS      :=
UNIT_SRC   :=
DUNIT_SRC  :=
IT_SRC     :=
BENCH_SRC  :=

# ---- links (used by the module.mk files) -------------------------------------------------------
CORE_LIB   := $(LIB)/libtandem.a
COMMON_LIB := $(LIB)/libtandem_daemon.a
DLIBS      := $(COMMON_LIB) $(LIB)/libtandem_lcm.a $(CORE_LIB)
# $(call link,EXTRA_LIBS): the target from its object prerequisites and DLIBS
define link
	@mkdir -p $(@D)
	@$(if $(Q),echo '  LD    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $(filter %.o,$^) $(DLIBS) $(PKG_LIBS) $(1) $(LDLIBS)
endef
# $(call program,NAME,OBJECTS): build/bin/NAME from OBJECTS
define program
$(BIN)/$(1): $(2) $$(DLIBS)
	$$(call link,)
endef
# $(call unit_tests,D): test/unit/D/test_*.c, compiled against the core only
# (the public headers, and domain D's private ones)
define unit_tests
UNIT_SRC += $$(wildcard test/unit/$(1)/test_*.c)
$$(OBJ)/test/unit/$(1)/%.o: DIR_CPPFLAGS = $$(UNIT_CPPFLAGS) -Isrc/core/$(1)
endef
UNIT_CPPFLAGS = $(CORE_INC) -Itest/unit -Itools/scenario -Isrc/platform/posix -D_POSIX_C_SOURCE=200809L
include src/core/layers.mk
include $(foreach d,$(CORE_DOMAINS),src/core/$(d)/module.mk)
include src/platform/module.mk src/daemons/common/module.mk
include src/daemons/arm/module.mk src/daemons/rover/module.mk src/daemons/supervisor/module.mk
include sim/models/module.mk sim/module.mk
include tools/module.mk tools/scenario/module.mk tools/netc/module.mk
include $(foreach d,$(CORE_DOMAINS),test/unit/$(d)/module.mk)
include test/common/module.mk test/netc/module.mk test/integration/module.mk bench/module.mk

CORE_OBJ   := $(patsubst %.c,$(OBJ)/%.o,$(CORE_SRC)) $(OBJ)/src/platform/posix/rtclock_posix.o
UNIT_BIN   := $(patsubst %.c,$(BIN)/%,$(notdir $(UNIT_SRC)))
DUNIT_BIN  := $(patsubst %.c,$(BIN)/%,$(notdir $(DUNIT_SRC)))
IT_BIN     := $(patsubst %.c,$(BIN)/%,$(notdir $(IT_SRC)))
BENCH_BIN  := $(patsubst %.c,$(BIN)/%,$(notdir $(BENCH_SRC)))

.PHONY: all run test unit integration bench coverage spy clean deps deps-bench deps-cross jar fuzz multihost-test fleet-hosts lint
all: $(PROGS) $(UNIT_BIN) $(DUNIT_BIN) $(IT_BIN) $(TYPES_JAR)

# make cross, make test-cross, make budget: the core on a 68040 and a Cortex-M4
include cross/cross.mk

# ---- Debian packages (installs when root, else prints the command) ---------
deps:
	@tools/deps.sh run
deps-bench:
	@tools/deps.sh bench
deps-cross:
	@tools/deps.sh cross

# ---- messages --------------------------------------------------------------
$(GEN_STAMP): $(LCM_FILES) lcmtypes/capacities tools/wire/lcm-wire-gen.awk
	@mkdir -p $(GEN)/c $(GEN)/java
	@lcm-gen -c --c-cpath $(GEN)/c --c-hpath $(GEN)/c $(LCM_FILES)
	@awk -v OUT=$(GEN)/c -f tools/wire/lcm-wire-gen.awk lcmtypes/capacities $(LCM_FILES)
	@lcm-gen -j --jpath $(GEN)/java $(LCM_FILES)
	@touch $@
# lcm-gen's C is not ours: built without -Werror, all of it in one step
$(LIB)/libtandem_lcm.a: $(GEN_STAMP)
	@mkdir -p $(OBJ)/gen $(LIB)
	@for f in $(GEN)/c/*.c; do \
	  $(CC) -std=c99 $(OPT) $(PKG_CFLAGS) -I$(GEN)/c -Isrc/daemons/common -c $$f -o $(OBJ)/gen/$$(basename $$f .c).o || exit 1; done
	@rm -f $@ && ar rcs $@ $(OBJ)/gen/*.o
$(TYPES_JAR): $(GEN_STAMP)
	@mkdir -p build/lib build/javaclasses
	@javac -nowarn -d build/javaclasses -cp /usr/share/java/lcm.jar $$(find $(GEN)/java -name '*.java') 2>&1 | grep -v '^Note:' || true
	@jar cf $@ -C build/javaclasses .
jar: $(TYPES_JAR)

# ---- the one compile recipe ---------------------------------------------------
# DIR_CPPFLAGS is set per folder by its module.mk (pattern-specific); the
# core's folders get only their layer's include paths and the poisoned
# POSIX/stdio headers, everything above the core gets all of it plus LCM.
$(OBJ)/%.o: %.c | $(GEN_STAMP) $(CORE_POISON) $(LAYER_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(DIR_CPPFLAGS) $(CFLAGS) -MMD -MP -c $< -o $@

$(CORE_LIB): $(CORE_OBJ)
	@mkdir -p $(@D)
	@rm -f $@ && ar rcs $@ $^
$(COMMON_LIB): $(patsubst %.c,$(OBJ)/%.o,$(COMMON_SRC))
	@mkdir -p $(@D)
	@rm -f $@ && ar rcs $@ $^
# tests: one object each (integration tests add the harness)
$(BIN)/test_%: $(DLIBS)
	$(call link,$(CMOCKA_LIBS))
$(BIN)/it_%: $(OBJ)/test/integration/harness.o $(DLIBS)
	$(call link,$(CMOCKA_LIBS))
$(BIN)/bench_%: $(DLIBS)
	$(call link,)
$(foreach s,$(UNIT_SRC) $(DUNIT_SRC) $(IT_SRC) $(BENCH_SRC),$(eval $(BIN)/$(notdir $(s:.c=)): $(OBJ)/$(s:.c=.o)))

unit: $(UNIT_BIN) $(DUNIT_BIN)
	@tools/run-tests.sh unit $(BIN) $(UNIT_BIN) $(DUNIT_BIN)
integration: $(PROGS) $(IT_BIN)
	@tools/run-tests.sh integration $(BIN) $(IT_BIN)

test: deps deps-cross
	@$(MAKE) --no-print-directory lint
	@$(MAKE) --no-print-directory all
	@$(MAKE) --no-print-directory unit integration
	@$(MAKE) --no-print-directory SAN=1 unit integration

# line and branch coverage (gcovr) of the unit and integration tests, the
# core's figure first: build/cov, then the summaries
coverage: deps
	@tools/deps.sh coverage
	@$(MAKE) --no-print-directory COV=1 all
	@find build/cov -name '*.gcda' -delete
	@$(MAKE) --no-print-directory COV=1 unit integration
	@tools/coverage.sh build/cov

run: deps $(if $(VIEW),viewer)
	@$(MAKE) --no-print-directory all
	@tools/tandem-run $(if $(DURATION),--duration $(DURATION)) $(if $(VIEW),--view) $(RUN_ARGS)

# the KDL baselines (C++): only make bench builds them
$(BIN)/bench_kdl $(BIN)/bench_tdsd_kdl: $(BIN)/%: bench/%.cpp bench/bench_pair.hpp $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CXX   $@';) true
	$(Q)$(CXX) -O2 -std=c++14 $(CORE_INC) $$(pkg-config --cflags orocos-kdl) $< $(CORE_LIB) $$(pkg-config --libs orocos-kdl) -lm -o $@

# Pinocchio (PyPI pin: its C++ headers and library in the cmeel prefix of
# the Python that make bench installs it into); only make bench builds it
# the definitions Pinocchio's CMake config gives its users (its joint
# variant has more types than Boost.MPL's preprocessed headers hold)
PIN_DEFS = -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 \
           -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_FUSION_INVOKE_MAX_ARITY=12
PIN_PREFIX = $(shell python3 -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])' 2>/dev/null)/cmeel.prefix
$(BIN)/bench_pinocchio: bench/bench_pinocchio.cpp bench/bench_pair.hpp $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CXX   $@';) true
	$(Q)$(CXX) -O3 -DNDEBUG -std=c++17 $(PIN_DEFS) $(CORE_INC) -isystem $(PIN_PREFIX)/include $$(pkg-config --cflags eigen3) $< $(CORE_LIB) \
	    -L$(PIN_PREFIX)/lib -lpinocchio_default -Wl,-rpath,$(PIN_PREFIX)/lib -lm -o $@

bench: deps deps-bench
	@$(MAKE) --no-print-directory all $(BENCH_BIN) $(BIN)/bench_kdl $(BIN)/bench_tdsd_kdl
	@python3 -c 'import pinocchio' 2>/dev/null || python3 -m pip install --quiet pin || \
	    echo "bench: pip install pin failed: no Pinocchio baseline"
	@$(MAKE) --no-print-directory $(BIN)/bench_pinocchio || echo "bench: bench_pinocchio not built"
	@tools/bench.sh $(BIN)

# libFuzzer (clang): every message type's wire check + decoder + validators
# for FUZZ_SECONDS each (tools/fuzz.sh); fails on any crash, leak or report
FUZZ_SECONDS ?= 10
fuzz: $(GEN_STAMP) $(GEN)/c/tandem_version.h
	@tools/deps.sh fuzz
	@tools/fuzz.sh $(FUZZ_SECONDS)

# the cell on three network namespaces joined by a bridge (udpm ttl=1)
# against one host: the same lockstep state hash (needs root)
multihost-test: deps $(PROGS)
	@command -v ip >/dev/null || { apt-get update -qq && apt-get install -y -qq iproute2; }
	@tools/multihost-test.sh

# TEAMS (30: 300 robots), HOSTS (4), MAX_TIME (8), ONE=0: the hosts' run alone
fleet-hosts: deps $(PROGS)
	@command -v ip >/dev/null || { apt-get update -qq && apt-get install -y -qq iproute2; }
	@tools/fleet-hosts.sh

spy: $(TYPES_JAR)
	@tools/spy.sh $(TYPES_JAR)

clean:
	rm -rf build

include tools/extra.mk tools/checks.mk

-include $(shell find build -name '*.d' 2>/dev/null)
.SECONDARY:
