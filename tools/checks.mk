# The checks beside the compiler, included by the Makefile:
#   make lint          (also) no mutable state at file scope in src/ (tools/lint-state.sh)
#   make analyze       cppcheck over every C file of the tree, zero findings
#   make format-check  clang-format (.clang-format) on every C file .clang-format-files names
#   make format        rewrites those files in that style
#   make tidy          clang-tidy (.clang-tidy) over every C file of the tree, zero findings
# analyze and format-check install their Debian package if missing
# (tools/deps.sh analyze), tidy its own (tools/deps.sh tidy); .ci/run calls
# them after make test.

# ---- state: every object of src/, the bare board's clock too --------------
STATE_SRC := $(wildcard src/*/*/*.c)
STATE_OBJ := $(patsubst %.c,$(OBJ)/%.o,$(STATE_SRC))
$(OBJ)/src/platform/board/%.o: DIR_CPPFLAGS = -Iinclude/tandem/base -Isrc/platform/board
lint: $(STATE_OBJ)

# ---- cppcheck -------------------------------------------------------------------
# Every tracked C file (C++ is the KDL baseline's, not ours), with the
# include paths of the build; findings it cannot see through are suppressed
# in tools/cppcheck-suppressions.xml, each by check, file and symbol with
# its reason (no line numbers: an edit above must not re-open one).
CPPCHECK_INC := $(CORE_INC) -Isrc/daemons/common -Isrc/platform/posix -I$(GEN)/c -Isim -Isim/models \
                -Itools/scenario -Itools/netc -Itest/unit -Itest/integration \
                $(foreach d,$(CORE_DOMAINS),-Isrc/core/$(d)) $(addprefix -I,$(wildcard src/daemons/*))
analyze: $(GEN_STAMP) $(GEN)/c/tandem_version.h
	@tools/deps.sh analyze
	@mkdir -p build/cppcheck
	@git ls-files '*.c' ':!third_party' > build/cppcheck/files
	@echo "  CPPCHECK $$(wc -l < build/cppcheck/files) files"
	$(Q)cppcheck -q -j2 --std=c99 --enable=warning,portability,performance --inline-suppr \
	  --suppress=missingIncludeSystem --suppress-xml=tools/cppcheck-suppressions.xml \
	  $(CPPCHECK_INC) -D_POSIX_C_SOURCE=200809L --cppcheck-build-dir=build/cppcheck \
	  --template='{file}:{line}: {severity} ({id}): {message}' --error-exitcode=1 \
	  --file-list=build/cppcheck/files
	@echo "analyze: cppcheck finds nothing"

# ---- clang-format ---------------------------------------------------------------
# .clang-format-files holds git pathspecs (every C file but those it leaves out)
FORMAT_FILES = $(shell sed -e 's/\#.*//' -e '/^[[:space:]]*$$/d' -e "s/.*/'&'/" .clang-format-files | \
                 xargs git ls-files --)
format-check:
	@tools/deps.sh analyze
	@bad=0; for f in $(FORMAT_FILES); do \
	  clang-format --style=file "$$f" | diff -u --label "$$f" --label "$$f (clang-format)" "$$f" - || bad=1; \
	done; \
	[ $$bad -eq 0 ] && echo "format-check: $(words $(FORMAT_FILES)) files in the style of .clang-format" || \
	{ echo "format-check: make format rewrites them (the files .clang-format-files names)"; exit 1; }
format:
	@tools/deps.sh analyze
	$(Q)clang-format --style=file -i $(FORMAT_FILES)

# ---- clang-tidy -------------------------------------------------------------------
# Every tracked C file with the include paths of the build (as cppcheck);
# the checks are .clang-tidy's. Three files are compiled with flags of their
# own (a generated list, a generated header, the fuzzed type): they get them.
TIDY_FLAGS := -std=c99 -D_POSIX_C_SOURCE=200809L $(CPPCHECK_INC) -Isrc/platform/board -Icross/budget \
              $(PKG_CFLAGS)
TIDY_OWN   := fuzz/fuzz_msg.c tools/scenario/scenario_main.c test/netc/test_netc_gen.c
TIDY_FLAGS_fuzz/fuzz_msg.c := -DFUZZ_TYPE=tandem_action_row_t '-DFUZZ_HEADER="tandem_action_row_t.h"' \
                              -DFUZZ_ACTION_ROW
TIDY_FLAGS_tools/scenario/scenario_main.c := '-DSCENARIO_LIST=$(SCEN_LIST)'
TIDY_FLAGS_test/netc/test_netc_gen.c := -I$(NETC_GEN)
tidy: $(GEN_STAMP) $(GEN)/c/tandem_version.h $(NETC_GEN)/carry_task.h
	@tools/deps.sh tidy
	@mkdir -p build/tidy
	@git ls-files '*.c' ':!third_party' $(foreach f,$(TIDY_OWN),':!$(f)') > build/tidy/files
	@echo "  TIDY  $$(( $$(wc -l < build/tidy/files) + $(words $(TIDY_OWN)) )) files"
	@rc=0; xargs -a build/tidy/files -P2 -n8 sh -c 'clang-tidy --quiet "$$@" -- $(TIDY_FLAGS)' tidy \
	  > build/tidy/out 2> build/tidy/err || rc=1; \
	$(foreach f,$(TIDY_OWN),clang-tidy --quiet $(f) -- $(TIDY_FLAGS) $(TIDY_FLAGS_$(f)) \
	  >> build/tidy/out 2>> build/tidy/err || rc=1;) \
	if [ $$rc -ne 0 ] || grep -q 'warning:\|error:' build/tidy/out; then \
	  cat build/tidy/out; grep -v 'warnings\? generated\|Suppressed\|Use -header-filter\|^$$' build/tidy/err; \
	  echo "tidy: clang-tidy finds the above (.clang-tidy; NOLINTNEXTLINE(check) with the reason)"; exit 1; \
	fi; echo "tidy: clang-tidy finds nothing"

.PHONY: analyze format-check format tidy
