# sim/: tandem-sim, the ODE world stepped in lockstep with the daemons
SIM_SRC += $(wildcard sim/*.c)
$(OBJ)/sim/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
PROGS += $(BIN)/tandem-sim
$(eval $(call program,tandem-sim,$(patsubst %.c,$(OBJ)/%.o,$(SIM_SRC))))
