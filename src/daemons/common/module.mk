# src/daemons/common: the daemon shell every program links (loop, bus, message
# checks, authentication, journal, process control) -> libtandem_daemon.a
COMMON_SRC := $(wildcard src/daemons/common/*.c)
$(OBJ)/src/daemons/common/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
