# daemons/supervisor: tandem-supervisor: the carry's Petri-net supervisor
$(OBJ)/daemons/supervisor/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Idaemons/supervisor
PROGS += $(BIN)/tandem-supervisor
$(eval $(call program,tandem-supervisor,$(patsubst %.c,$(OBJ)/%.o,$(wildcard daemons/supervisor/*.c))))
