# daemons/arm: tandem-arm: one PUMA 560's controller (joint, event-referenced Cartesian, TDSD)
$(OBJ)/daemons/arm/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Idaemons/arm
PROGS += $(BIN)/tandem-arm
$(eval $(call program,tandem-arm,$(patsubst %.c,$(OBJ)/%.o,$(wildcard daemons/arm/*.c))))
