# tools/: user commands, one file each: tools/tandem_<name>.c -> tandem-<name>
TOOL_SRC := $(wildcard tools/tandem_*.c)
$(OBJ)/tools/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
PROGS += $(patsubst tools/tandem_%.c,$(BIN)/tandem-%,$(TOOL_SRC))
$(foreach s,$(TOOL_SRC),$(eval $(call program,$(subst tandem_,tandem-,$(basename $(notdir $(s)))),$(OBJ)/$(s:.c=.o))))
