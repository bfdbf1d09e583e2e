# tools/netc: tandem-netc, the task compiler (docs/tasks.md): PNML and rows
# in, checked, const tables out. The reader and checker are the daemon
# shell's (src/daemons/common/netc_*.c, libxml2 for the PNML), shared with
# tandem-supervisor --task; the C writer is the tool's own.
NETC_SRC  := $(filter-out tools/netc/netc_main.c,$(wildcard tools/netc/*.c))
NETC_OBJ  := $(patsubst %.c,$(OBJ)/%.o,$(NETC_SRC))
$(OBJ)/tools/netc/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Itools/netc
PROGS += $(BIN)/tandem-netc
$(eval $(call program,tandem-netc,$(OBJ)/tools/netc/netc_main.o $(NETC_OBJ)))
