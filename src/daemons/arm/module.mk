# src/daemons/arm: tandem-arm: one PUMA 560's controller (joint, event-referenced Cartesian, TDSD)
$(OBJ)/src/daemons/arm/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Isrc/daemons/arm
PROGS += $(BIN)/tandem-arm
$(eval $(call program,tandem-arm,$(patsubst %.c,$(OBJ)/%.o,$(wildcard src/daemons/arm/*.c))))
