# test/netc: tests of tandem-netc (tools/netc, host only). test_netc links
# its modules; test_netc_gen links the C it writes for the shipped carry.
NETC_GEN := $(GEN)/tasks
DUNIT_SRC += test/netc/test_netc.c test/netc/test_netc_gen.c test/netc/test_task_load.c
$(OBJ)/test/netc/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS) -I$(NETC_GEN)
$(OBJ)/$(NETC_GEN)/%.o: DIR_CPPFLAGS = $(APP_CPPFLAGS)
$(BIN)/test_netc: $(NETC_OBJ)
$(BIN)/test_netc_gen: $(OBJ)/$(NETC_GEN)/carry_task.o
$(OBJ)/test/netc/test_netc_gen.o: $(NETC_GEN)/carry_task.h
$(NETC_GEN)/carry_task.h: $(NETC_GEN)/carry_task.c
$(NETC_GEN)/carry_task.c: tasks/carry/carry.pnml tasks/carry/rows.csv $(BIN)/tandem-netc
	@mkdir -p $(@D)
	$(Q)$(BIN)/tandem-netc tasks/carry/carry.pnml tasks/carry/rows.csv --out $(@D) >/dev/null
