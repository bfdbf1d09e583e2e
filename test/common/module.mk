# test/common: unit tests of the daemon shell (src/daemons/common); host only
DUNIT_SRC := $(wildcard test/common/test_*.c)
$(OBJ)/test/common/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
