# src/platform/: the clock behind include/tandem/base/rtloop.h. posix/ goes into
# the host core library; board/ is the bare-metal one, built by make cross only.
$(OBJ)/src/platform/posix/%.o: DIR_CPPFLAGS = -Iinclude/tandem/base -D_POSIX_C_SOURCE=200809L
