# src/daemons/rover: tandem-rover: one or more Pioneers' formation controllers
$(OBJ)/src/daemons/rover/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Isrc/daemons/rover
PROGS += $(BIN)/tandem-rover
$(eval $(call program,tandem-rover,$(patsubst %.c,$(OBJ)/%.o,$(wildcard src/daemons/rover/*.c))))
