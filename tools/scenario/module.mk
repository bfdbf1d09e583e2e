# tools/scenario: tandem-scenario. Every scenario_<name>.c but main and
# util defines scenario_<name>; the list is compiled into scenario_main.c.
# The other .c files here (carry_*.c, formation_*.c, tdsd_*.c,
# shared_run.c, hang_watch.c, run_key.c) are linked in.
SCEN_SRC   := $(wildcard tools/scenario/*.c)
SCEN_NAMES := $(filter-out main util,$(patsubst tools/scenario/scenario_%.c,%,$(filter tools/scenario/scenario_%.c,$(SCEN_SRC))))
SCEN_LIST  := $(foreach n,$(SCEN_NAMES),&scenario_$(n),)
$(OBJ)/tools/scenario/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Itools/scenario
$(OBJ)/tools/scenario/scenario_main.o: DIR_CPPFLAGS += '-DSCENARIO_LIST=$(SCEN_LIST)'
$(OBJ)/tools/scenario/scenario_main.o: tools/scenario/module.mk $(SCEN_SRC)
PROGS += $(BIN)/tandem-scenario
$(eval $(call program,tandem-scenario,$(patsubst %.c,$(OBJ)/%.o,$(SCEN_SRC))))
