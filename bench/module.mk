# bench/: make bench (tools/bench.sh) prints figures, asserts nothing; the
# KDL baselines (*.cpp) are built by the Makefile's bench rules
BENCH_SRC := $(wildcard bench/bench_*.c)
$(OBJ)/bench/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -Itest/unit -Isim/models -Isim
