# test/common: unit tests of the daemon shell (src/daemons/common); host only
DUNIT_SRC := $(wildcard test/common/test_*.c)
$(OBJ)/test/common/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
# the scenario's hang watch is tested here too (it needs the bus, as these do)
$(OBJ)/test/common/test_hang_watch.o: DIR_CPPFLAGS += -Itools/scenario
$(BIN)/test_hang_watch: $(OBJ)/tools/scenario/hang_watch.o $(OBJ)/tools/scenario/scenario_util.o $(OBJ)/tools/scenario/scen_status.o
# the status texts of tandem-sim and tandem-scenario (their code lists)
$(OBJ)/test/common/test_tool_status.o: DIR_CPPFLAGS += -Itools/scenario
$(BIN)/test_tool_status: $(OBJ)/sim/sim_status.o $(OBJ)/tools/scenario/scen_status.o
# what tandem-scenario measures of a world (its way, passage and cut)
$(OBJ)/test/common/test_formation_way.o: DIR_CPPFLAGS += -Itools/scenario
$(BIN)/test_formation_way: $(OBJ)/tools/scenario/formation_way.o
# the sweep's lists in turn (--robots 3,4,6,8 --formation line,triangle,column)
$(OBJ)/test/common/test_sweep_in_turn.o: DIR_CPPFLAGS += -Itools/scenario
$(BIN)/test_sweep_in_turn: $(OBJ)/tools/scenario/sweep_worlds.o $(OBJ)/tools/scenario/scenario_util.o $(OBJ)/tools/scenario/scen_status.o
