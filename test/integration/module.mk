# test/integration: the real daemons and simulator on a private bus; each
# it_<name>.c is one program linked with harness.c
IT_SRC := $(wildcard test/integration/it_*.c)
$(OBJ)/test/integration/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Itest/integration
# it_rover_far holds the simulator's rover model in process, as bench_fleet does
$(OBJ)/test/integration/it_rover_far.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Itest/integration -Isim/models -Isim
