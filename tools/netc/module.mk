# tools/netc: tandem-netc, the task compiler (docs/tasks.md): PNML and rows
# in, checked, const tables out. libxml2 reads the PNML.
NETC_SRC  := $(filter-out tools/netc/netc_main.c,$(wildcard tools/netc/*.c))
NETC_OBJ  := $(patsubst %.c,$(OBJ)/%.o,$(NETC_SRC))
$(OBJ)/tools/netc/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Itools/netc
PROGS += $(BIN)/tandem-netc
$(eval $(call program,tandem-netc,$(OBJ)/tools/netc/netc_main.o $(NETC_OBJ)))
