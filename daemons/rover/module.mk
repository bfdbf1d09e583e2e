# daemons/rover: tandem-rover: one or more Pioneers' formation controllers
$(OBJ)/daemons/rover/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Idaemons/rover
PROGS += $(BIN)/tandem-rover
$(eval $(call program,tandem-rover,$(patsubst %.c,$(OBJ)/%.o,$(wildcard daemons/rover/*.c))))
