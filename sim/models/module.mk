# sim/models: the ODE models of the arm cell, the workpieces and the rovers
SIM_SRC := $(wildcard sim/models/*.c)
$(OBJ)/sim/models/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
