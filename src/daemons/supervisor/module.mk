# src/daemons/supervisor: tandem-supervisor: the carry's Petri-net supervisor
$(OBJ)/src/daemons/supervisor/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Isrc/daemons/supervisor
PROGS += $(BIN)/tandem-supervisor
$(eval $(call program,tandem-supervisor,$(patsubst %.c,$(OBJ)/%.o,$(wildcard src/daemons/supervisor/*.c))))
