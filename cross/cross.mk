# cross/cross.mk (included by the Makefile): the pure core built for the
# boards it is written for, checked there, and its budgets measured.
#   make cross       core library for m68k-linux-gnu (-m68040, big-endian) and
#                    arm-none-eabi (Cortex-M4F, hard float, newlib), same
#                    warnings as the host; fails if a POSIX or stdio header is
#                    reachable from the core or the core calls outside
#                    libm / string.h / the platform clock
#   make test-cross  the CMocka unit tests built for the 68040 (static ELF,
#                    big-endian) and run under qemu-m68k-static -cpu m68040
#   make budget      text/data/bss per module, worst-case stack per
#                    per-cycle entry point, instructions and 25 MHz 68040
#                    time per cycle (cross/budget.sh)
# Output only under build/cross/ and build/poison/.

CROSS       := build/cross
M68K_CC     := m68k-linux-gnu-gcc
M68K_ARCH   := -m68040
CM4_CC      := arm-none-eabi-gcc
CM4_ARCH    := -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16
# the core's flags on every target; -fstack-usage and -fcallgraph-info give
# the per-function frames and call edges make budget adds up
CROSS_CFLAGS := $(WARN) -O2 -fstack-usage -fcallgraph-info=su
QEMU_M68K   := qemu-m68k-static -cpu m68040

# ---- the core stays ISO C99 + libm -----------------------------------------
# Each header here is replaced, for core compiles only, by one that stops
# the build: the core must not reach it directly or through another header.
CORE_FORBIDDEN := stdio.h stdlib.h malloc.h unistd.h time.h pthread.h sched.h \
                  signal.h setjmp.h fcntl.h poll.h semaphore.h termios.h dirent.h \
                  dlfcn.h sys/types.h sys/time.h sys/stat.h sys/mman.h \
                  sys/socket.h sys/select.h netinet/in.h arpa/inet.h
CORE_POISON := build/poison
$(CORE_POISON): cross/cross.mk
	@rm -rf $@
	@for h in $(CORE_FORBIDDEN); do mkdir -p $@/$$(dirname $$h); \
	  printf '#error "<%s> reached from the pure core: src/core/ is ISO C99 + libm only; platform code goes in src/platform/"\n' $$h > $@/$$h; done

# ---- per-target core library -------------------------------------------------
CORE_NAMES := $(patsubst src/core/%.c,%,$(CORE_SRC))

# $(1) target name, $(2) compiler, $(3) arch flags
define cross_target
$(1)_CORE_OBJ := $$(patsubst %,$(CROSS)/$(1)/core/%.o,$(CORE_NAMES))
$(foreach d,$(CORE_DOMAINS),$(CROSS)/$(1)/core/$(d)/%.o: DIR_CPPFLAGS = $$(call core_cppflags,$(d))
)
$(CROSS)/$(1)/core/%.o: src/core/%.c | $(CORE_POISON) $(LAYER_STAMP)
	@mkdir -p $$(@D)
	@$$(if $$(Q),echo '  CC    $$@';) true
	$$(Q)$(2) $(3) $$(DIR_CPPFLAGS) $$(CROSS_CFLAGS) -MMD -MP -c $$< -o $$@
$(CROSS)/$(1)/libtandem.a: $$($(1)_CORE_OBJ)
	@rm -f $$@ && $(2)-ar rcs $$@ $$^
	@cross/check-core-calls.sh $(subst gcc,nm,$(2)) $$@
# the bare-board clock (src/platform/board) must build freestanding too
$(CROSS)/$(1)/platform/rtclock_board.o: src/platform/board/rtclock_board.c
	@mkdir -p $$(@D)
	@$$(if $$(Q),echo '  CC    $$@';) true
	$$(Q)$(2) $(3) -ffreestanding -Iinclude/tandem/base -Isrc/platform/board -I$(CORE_POISON) $$(CROSS_CFLAGS) -MMD -MP -c $$< -o $$@
endef
$(eval $(call cross_target,m68k,$(M68K_CC),$(M68K_ARCH)))
$(eval $(call cross_target,cm4,$(CM4_CC),$(CM4_ARCH)))

CROSS_LIBS := $(CROSS)/m68k/libtandem.a $(CROSS)/cm4/libtandem.a \
              $(CROSS)/m68k/platform/rtclock_board.o $(CROSS)/cm4/platform/rtclock_board.o

.PHONY: cross test-cross budget
cross: $(CROSS_LIBS)
	@echo "cross: core built for m68k-linux-gnu $(M68K_ARCH) and arm-none-eabi (Cortex-M4F): $(words $(CORE_NAMES)) modules each"

# ---- the unit tests on the 68040 ---------------------------------------------
# CMocka 1.1.5 (Apache-2.0, third_party/cmocka) built for the target; the
# tests link the core, the POSIX clock (m68k Linux has one) and glibc.
M68K_TEST_FLAGS = $(M68K_ARCH) $(WARN) -O2 $(UNIT_CPPFLAGS) -Ithird_party/cmocka
M68K_UNIT_BIN := $(patsubst %.c,$(CROSS)/m68k/bin/%,$(notdir $(UNIT_SRC)))
$(CROSS)/m68k/cmocka.o: third_party/cmocka/cmocka.c
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(M68K_CC) $(M68K_ARCH) -std=gnu99 -O2 -w -Ithird_party/cmocka $(CMOCKA_DEFS) -c $< -o $@
CMOCKA_DEFS := -DHAVE_SIGNAL_H -DHAVE_STRINGS_H -DHAVE_INTTYPES_H -DHAVE_MALLOC_H -DHAVE_STRUCT_TIMESPEC \
               -DHAVE_CLOCK_GETTIME -DHAVE_CLOCK_REALTIME -DHAVE_SIGLONGJMP -DHAVE_STRSIGNAL
$(CROSS)/m68k/platform/rtclock_posix.o: src/platform/posix/rtclock_posix.c
	@mkdir -p $(@D)
	$(Q)$(M68K_CC) $(M68K_ARCH) $(WARN) -O2 -Iinclude/tandem/base -D_POSIX_C_SOURCE=200809L -c $< -o $@
# each test sees the core's public headers and its own domain's private ones
$(foreach s,$(UNIT_SRC),$(eval $(CROSS)/m68k/bin/$(notdir $(s:.c=)): $(s)) \
  $(eval $(CROSS)/m68k/bin/$(notdir $(s:.c=)): M68K_TEST_PRIV = -I$(patsubst test/unit/%/,src/core/%,$(dir $(s)))))
$(CROSS)/m68k/bin/test_%: $(CROSS)/m68k/libtandem.a $(CROSS)/m68k/cmocka.o $(CROSS)/m68k/platform/rtclock_posix.o
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(M68K_CC) $(M68K_TEST_FLAGS) $(M68K_TEST_PRIV) -MMD -MP -static -o $@ $(filter %.c,$^) $(CROSS)/m68k/cmocka.o \
	    $(CROSS)/m68k/platform/rtclock_posix.o $(CROSS)/m68k/libtandem.a -lm

test-cross: deps-cross
	@$(MAKE) --no-print-directory cross $(M68K_UNIT_BIN)
	@cross/check-elf.sh $(M68K_UNIT_BIN)
	@TEST_RUNNER="$(QEMU_M68K)" tools/run-tests.sh unit-m68040 $(CROSS)/m68k/bin $(M68K_UNIT_BIN)

# ---- budgets -----------------------------------------------------------------
# $(1) target name, $(2) compiler, $(3) arch flags: the entry points, for the call graph
define cross_budget
$(CROSS)/$(1)/budget/cycles.o: cross/budget/cycles.c | $(CORE_POISON)
	@mkdir -p $$(@D)
	$$(Q)$(2) $(3) $(CORE_INC) -I$(CORE_POISON) $$(CROSS_CFLAGS) -MMD -MP -c $$< -o $$@
endef
$(eval $(call cross_budget,m68k,$(M68K_CC),$(M68K_ARCH)))
$(eval $(call cross_budget,cm4,$(CM4_CC),$(CM4_ARCH)))
$(CROSS)/m68k/bin/budget: cross/budget/budget_main.c $(CROSS)/m68k/budget/cycles.o $(CROSS)/m68k/libtandem.a
	@mkdir -p $(@D)
	@$(if $(Q),echo '  CC    $@';) true
	$(Q)$(M68K_CC) $(M68K_ARCH) $(WARN) -O2 $(CORE_INC) -Icross/budget -MMD -MP -static -o $@ $< \
	    $(CROSS)/m68k/budget/cycles.o $(CROSS)/m68k/libtandem.a -lm

budget: deps-cross
	@$(MAKE) --no-print-directory cross $(CROSS)/m68k/bin/budget $(CROSS)/m68k/budget/cycles.o $(CROSS)/cm4/budget/cycles.o
	@cross/budget.sh $(CROSS) $(CROSS)/m68k/bin/budget
