# The checks beside the compiler, included by the Makefile:
#   make lint          (also) no mutable state at file scope in src/ (tools/lint-state.sh)
#   make analyze       cppcheck over every C file of the tree, zero findings
#   make format-check  clang-format (.clang-format) on every C file .clang-format-files names
#   make format        rewrites those files in that style
# analyze and format-check install their Debian package if missing
# (tools/deps.sh analyze); .ci/run calls both after make test.

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

.PHONY: analyze format-check format
