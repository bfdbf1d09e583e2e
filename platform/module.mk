# platform/: the clock behind core/base/rtloop.h. posix/ goes into the host
# core library; board/ is the bare-metal one, built by make cross only.
$(OBJ)/platform/posix/%.o: DIR_CPPFLAGS = -Icore/base -D_POSIX_C_SOURCE=200809L
