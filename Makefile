# tandem: one Makefile. Build output goes only under build/ (bin/, lib/, gen/).
#   make            build everything (core library, messages, daemons, sim, tools)
#   make run        install missing Debian packages, then run the whole system
#   make test       install missing packages, then unit + integration tests,
#                   also rebuilt and rerun with -fsanitize=address,undefined
#   make bench      benchmarks (figures printed, nothing asserted)
#   make spy        lcm-spy with every tandem channel decoded
#   make cross      the core for m68k-linux-gnu (-m68040) and arm-none-eabi (Cortex-M4F)
#   make test-cross the unit tests built for the 68040, run under qemu-m68k
#   make budget     memory, stack and cycle budgets of the cross builds
#   make view       live 3D viewer in the browser (also: make run VIEW=1)
#   make multihost-test  the cell on three network namespaces (root)
#   make help       every target and variable
#   make clean
# SAN=1 builds into build/san with the sanitizers on.

CC       ?= cc
# quiet by default; V=1 shows every command
Q        := $(if $(V),,@)
PKGS     := lcm ode ccd libsodium
WARN     := -std=c99 -Wall -Wextra -Wpedantic -Werror
OPT      ?= -O2 -g
ifeq ($(SAN),1)
BUILD    := build/san
OPT      := -O1 -g -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=undefined
LDSAN    := -fsanitize=address,undefined
else
BUILD    := build
endif
BIN      := $(BUILD)/bin
LIB      := $(BUILD)/lib
OBJ      := $(BUILD)/obj
GEN      := build/gen
PKG_CFLAGS := $(shell pkg-config --cflags $(PKGS) 2>/dev/null)
PKG_LIBS   := $(shell pkg-config --libs $(PKGS) 2>/dev/null)
CMOCKA_LIBS := $(shell pkg-config --libs cmocka 2>/dev/null)
CPPFLAGS := -Iinclude -Itest -I$(GEN)/c -Idaemons/common -Isim -D_POSIX_C_SOURCE=200809L
CFLAGS   := $(WARN) $(OPT)
LDLIBS   := -lm

# ---- sources ---------------------------------------------------------------
CORE_SRC   := $(wildcard src/*.c)
# the POSIX clock behind rtloop (include/rtclock.h) goes into the host library
CORE_OBJ   := $(patsubst src/%.c,$(OBJ)/core/%.o,$(CORE_SRC)) $(OBJ)/platform/rtclock_posix.o
CORE_LIB   := $(LIB)/libtandem.a
LCM_FILES  := $(wildcard lcmtypes/*.lcm)
GEN_STAMP  := $(GEN)/.stamp
COMMON_SRC := $(wildcard daemons/common/*.c)
COMMON_OBJ := $(patsubst daemons/common/%.c,$(OBJ)/common/%.o,$(COMMON_SRC))
COMMON_LIB := $(LIB)/libtandem_daemon.a
SIM_SRC    := $(wildcard sim/*.c)
SIM_OBJ    := $(patsubst sim/%.c,$(OBJ)/sim/%.o,$(SIM_SRC))
SCEN_SRC   := $(wildcard tools/scenario/*.c)
SCEN_OBJ   := $(patsubst tools/scenario/%.c,$(OBJ)/scenario/%.o,$(SCEN_SRC))
# every tools/scenario/scenario_<name>.c but main/util defines scenario_<name>;
# other .c files there (helpers such as tdsd_*.c) are linked in, not listed
SCEN_NAMES := $(filter-out main util,$(patsubst tools/scenario/scenario_%.c,%,$(filter tools/scenario/scenario_%.c,$(SCEN_SRC))))
SCEN_LIST  := $(foreach n,$(SCEN_NAMES),&scenario_$(n),)
# every daemons/tandem_<name>.c and tools/tandem_<name>.c is one program tandem-<name>
DAEMON_SRC := $(wildcard daemons/tandem_*.c)
TOOL_SRC   := $(wildcard tools/tandem_*.c)
PROGS      := $(patsubst daemons/tandem_%.c,$(BIN)/tandem-%,$(DAEMON_SRC)) \
              $(patsubst tools/tandem_%.c,$(BIN)/tandem-%,$(TOOL_SRC)) \
              $(BIN)/tandem-sim $(if $(SCEN_NAMES),$(BIN)/tandem-scenario)
UNIT_SRC   := $(wildcard test/test_*.c)
UNIT_BIN   := $(patsubst test/%.c,$(BIN)/%,$(UNIT_SRC))
# unit tests of the daemon layer (daemons/common): host only, never cross-built
DUNIT_SRC  := $(wildcard test/common/test_*.c)
DUNIT_BIN  := $(patsubst test/common/%.c,$(BIN)/%,$(DUNIT_SRC))
IT_SRC     := $(wildcard test/integration/it_*.c)
IT_BIN     := $(patsubst test/integration/%.c,$(BIN)/%,$(IT_SRC))
BENCH_SRC  := $(wildcard test/bench_*.c)
BENCH_BIN  := $(patsubst test/%.c,$(BIN)/%,$(BENCH_SRC))
TYPES_JAR  := build/lib/tandem_types.jar

.PHONY: all run test unit integration bench spy clean deps deps-bench deps-cross jar fuzz multihost-test
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
$(LIB)/libtandem_lcm.a: $(GEN_STAMP)
	@mkdir -p $(OBJ)/gen $(LIB)
	@for f in $(GEN)/c/*.c; do \
	  $(CC) -std=c99 $(OPT) $(PKG_CFLAGS) -I$(GEN)/c -Idaemons/common -c $$f -o $(OBJ)/gen/$$(basename $$f .c).o || exit 1; done
	@rm -f $@ && ar rcs $@ $(OBJ)/gen/*.o
$(TYPES_JAR): $(GEN_STAMP)
	@mkdir -p build/lib build/javaclasses
	@javac -nowarn -d build/javaclasses -cp /usr/share/java/lcm.jar $$(find $(GEN)/java -name '*.java') 2>&1 | grep -v '^Note:' || true
	@jar cf $@ -C build/javaclasses .
jar: $(TYPES_JAR)

# ---- libraries -------------------------------------------------------------
# the core sees only include/: no LCM, no ODE, pure C99 + libm; a POSIX or
# stdio header reached from it stops the build (CORE_POISON, cross/cross.mk)
$(OBJ)/core/%.o: src/%.c | $(CORE_POISON)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) -Iinclude -I$(CORE_POISON) $(CFLAGS) -MMD -c $< -o $@
$(OBJ)/platform/%.o: platform/posix/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) -Iinclude -D_POSIX_C_SOURCE=200809L $(CFLAGS) -MMD -c $< -o $@
$(CORE_LIB): $(CORE_OBJ)
	@mkdir -p $(@D)
	@rm -f $@ && ar rcs $@ $^
$(OBJ)/common/%.o: daemons/common/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(COMMON_LIB): $(COMMON_OBJ)
	@mkdir -p $(@D)
	@rm -f $@ && ar rcs $@ $^
DLIBS := $(COMMON_LIB) $(LIB)/libtandem_lcm.a $(CORE_LIB)

# ---- programs --------------------------------------------------------------
$(OBJ)/sim/%.o: sim/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(BIN)/tandem-sim: $(SIM_OBJ) $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $(SIM_OBJ) $(DLIBS) $(PKG_LIBS) $(LDLIBS)
$(OBJ)/scenario/%.o: tools/scenario/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) -Itools/scenario $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(OBJ)/scenario/scenario_main.o: tools/scenario/scenario_main.c $(GEN_STAMP) Makefile $(SCEN_SRC)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) -Itools/scenario $(CFLAGS) '-DSCENARIO_LIST=$(SCEN_LIST)' -MMD -c $< -o $@
$(BIN)/tandem-scenario: $(SCEN_OBJ) $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $(SCEN_OBJ) $(DLIBS) $(PKG_LIBS) $(LDLIBS)
$(OBJ)/prog/%.o: daemons/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(OBJ)/prog/%.o: tools/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(BIN)/tandem-%: $(OBJ)/prog/tandem_%.o $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $< $(DLIBS) $(PKG_LIBS) $(LDLIBS)

# ---- tests -----------------------------------------------------------------
$(OBJ)/test/%.o: test/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(BIN)/test_%: $(OBJ)/test/test_%.o $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $< $(DLIBS) $(PKG_LIBS) $(CMOCKA_LIBS) $(LDLIBS)
$(OBJ)/dtest/%.o: test/common/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(BIN)/test_%: $(OBJ)/dtest/test_%.o $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $< $(DLIBS) $(PKG_LIBS) $(CMOCKA_LIBS) $(LDLIBS)
$(OBJ)/it/%.o: test/integration/%.c $(GEN_STAMP)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(CPPFLAGS) -Itest/integration $(CFLAGS) $(PKG_CFLAGS) -MMD -c $< -o $@
$(BIN)/it_%: $(OBJ)/it/it_%.o $(OBJ)/it/harness.o $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $^ $(PKG_LIBS) $(CMOCKA_LIBS) $(LDLIBS)
$(BIN)/bench_%: $(OBJ)/test/bench_%.o $(DLIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(CC) $(OPT) $(LDSAN) -o $@ $< $(DLIBS) $(PKG_LIBS) $(LDLIBS)

unit: $(UNIT_BIN) $(DUNIT_BIN)
	@tools/run-tests.sh unit $(BIN) $(UNIT_BIN) $(DUNIT_BIN)
integration: $(PROGS) $(IT_BIN)
	@tools/run-tests.sh integration $(BIN) $(IT_BIN)

test: deps deps-cross
	@$(MAKE) --no-print-directory all
	@$(MAKE) --no-print-directory unit integration
	@$(MAKE) --no-print-directory SAN=1 unit integration

run: deps $(if $(VIEW),viewer)
	@$(MAKE) --no-print-directory all
	@tools/tandem-run $(if $(DURATION),--duration $(DURATION)) $(if $(VIEW),--view) $(RUN_ARGS)

$(BIN)/bench_kdl: test/bench_kdl.cpp $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CXX   $@';) true
	$(Q)$(CXX) -O2 -std=c++14 -Iinclude $$(pkg-config --cflags orocos-kdl) $< $(CORE_LIB) $$(pkg-config --libs orocos-kdl) -lm -o $@

$(BIN)/bench_tdsd_kdl: test/bench_tdsd_kdl.cpp $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CXX   $@';) true
	$(Q)$(CXX) -O2 -std=c++14 -Iinclude $$(pkg-config --cflags orocos-kdl) $< $(CORE_LIB) $$(pkg-config --libs orocos-kdl) -lm -o $@

bench: deps deps-bench
	@$(MAKE) --no-print-directory all $(BENCH_BIN) $(BIN)/bench_kdl $(BIN)/bench_tdsd_kdl
	@tools/bench.sh $(BIN)

# libFuzzer (clang): every message type's wire check + decoder + validators
# for FUZZ_SECONDS each (tools/fuzz.sh); fails on any crash, leak or report
FUZZ_SECONDS ?= 10
fuzz: $(GEN_STAMP)
	@command -v clang >/dev/null || tools/deps.sh fuzz
	@tools/fuzz.sh $(FUZZ_SECONDS)

# the cell on three network namespaces joined by a bridge (udpm ttl=1)
# against one host: the same lockstep state hash (needs root)
multihost-test: deps $(PROGS)
	@command -v ip >/dev/null || { apt-get update -qq && apt-get install -y -qq iproute2; }
	@tools/multihost-test.sh

spy: $(TYPES_JAR)
	@tools/spy.sh $(TYPES_JAR)

clean:
	rm -rf build

include tools/extra.mk

-include $(shell find build -name '*.d' 2>/dev/null)
.SECONDARY:
